#include "threads.hpp"

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace sphray::bench {
namespace {

// One arena per thread count, made once: creating an arena per pass would add its start-up
// to every timed pass.
tbb::task_arena& arena(int threads) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<tbb::task_arena>> arenas;
  const std::lock_guard lock(mutex);
  auto& a = arenas[threads];
  if (!a) a = std::make_unique<tbb::task_arena>(threads);
  return *a;
}

}  // namespace

int all_threads() {
  return tbb::info::default_concurrency();
}

void parallel_chunks(int threads, std::size_t count,
                     const std::function<void(std::size_t, std::size_t)>& chunk) {
  // About 16 chunks per thread keeps both cores busy to the end when rays differ in cost
  // (sky rays are cheap), without a chunk so small that scheduling shows.
  const std::size_t grain =
      std::clamp<std::size_t>(count / (16 * static_cast<std::size_t>(threads)), 1, 4096);
  arena(threads).execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, grain),
                      [&](const tbb::blocked_range<std::size_t>& r) { chunk(r.begin(), r.end()); });
  });
}

void run_on_threads(int threads, const std::function<void()>& work) {
  arena(threads).execute(work);
}

}  // namespace sphray::bench
