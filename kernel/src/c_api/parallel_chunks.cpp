#include "c_api/parallel_chunks.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include "sphray/sphray.h"

namespace sphray::c_api {

unsigned parallel_threads(std::size_t count, unsigned threads) {
  if (threads == SPHRAY_THREADS_ALL) threads = std::max(1u, std::thread::hardware_concurrency());
  threads = std::max(1u, threads);
  const std::size_t chunks = (count + kParallelChunk - 1) / kParallelChunk;
  return static_cast<unsigned>(std::max<std::size_t>(1, std::min<std::size_t>(threads, chunks)));
}

void run_chunks(std::size_t count, unsigned workers,
                void (*chunk)(void*, unsigned, std::size_t, std::size_t), void* context) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;  // the first exception a helper thread caught
  std::mutex failure_lock;
  auto work = [&](unsigned worker) {
    for (std::size_t begin; (begin = next.fetch_add(kParallelChunk)) < count;)
      chunk(context, worker, begin, std::min(count, begin + kParallelChunk));
  };
  // A helper's exception must not end the program (std::terminate): it stops the other
  // threads' work and is rethrown on the calling thread, which maps it to a status.
  auto helper = [&](unsigned worker) {
    try {
      work(worker);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(failure_lock);
      if (!failure) failure = std::current_exception();
      next = count;
    }
  };
  std::vector<std::thread> helpers;
  helpers.reserve(workers - 1);
  for (unsigned i = 1; i < workers; ++i) {
    try {
      helpers.emplace_back(helper, i);
    } catch (const std::system_error&) {
      break;  // no more threads to be had: the ones running do the rest
    }
  }
  try {
    work(0);
  } catch (...) {
    next = count;
    for (std::thread& t : helpers)
      t.join();
    throw;
  }
  for (std::thread& t : helpers)
    t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace sphray::c_api
