#include "c_api/parallel_chunks.hpp"

#include <algorithm>
#include <atomic>
#include <system_error>
#include <thread>
#include <vector>

namespace sphray::c_api {

unsigned parallel_threads(std::size_t count, unsigned threads) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t chunks = (count + kParallelChunk - 1) / kParallelChunk;
  return static_cast<unsigned>(std::max<std::size_t>(1, std::min<std::size_t>(threads, chunks)));
}

void run_chunks(std::size_t count, unsigned workers, void (*chunk)(void*, std::size_t, std::size_t),
                void* context) {
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t begin; (begin = next.fetch_add(kParallelChunk)) < count;)
      chunk(context, begin, std::min(count, begin + kParallelChunk));
  };
  std::vector<std::thread> helpers;
  helpers.reserve(workers - 1);
  for (unsigned i = 1; i < workers; ++i) {
    try {
      helpers.emplace_back(work);
    } catch (const std::system_error&) {
      break;  // no more threads to be had: the ones running do the rest
    }
  }
  work();
  for (std::thread& t : helpers)
    t.join();
}

}  // namespace sphray::c_api
