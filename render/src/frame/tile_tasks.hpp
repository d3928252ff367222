// The renderers' tile loop: ranges of tiles run as oneTBB tasks in the caller's arena.
//
// Under ThreadSanitizer the loop also states the happens-before edges oneTBB makes: what the
// caller did before the loop happens before every task, and every task before what the caller
// does after it. Debian's libtbb is not built with -fsanitize=thread, so TSan cannot see these
// edges by itself; .ci/tsan.supp drops the reports whose stacks run through libtbb, but a report
// whose other stack TSan could no longer restore (its history overwritten, as for a variable of
// one pass that a task read and the next pass wrote) slipped past it. With the edges stated there
// is no such report to drop (docs/robustness.md, "ThreadSanitizer and oneTBB").
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cstddef>

#if defined(__SANITIZE_THREAD__)
#define SPHRAY_RENDER_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define SPHRAY_RENDER_TSAN 1
#endif
#endif
#if SPHRAY_RENDER_TSAN
#include <sanitizer/tsan_interface.h>
#endif

namespace sphray::render {

/// Under collective queries, the most tiles a process traces together, one call a sample (or
/// a bounce, in path mode): 16,384 rays, enough for the exchanges between processes to pay,
/// few enough for the group's rays and hits to stay in the caches.
inline constexpr std::size_t kGroupTiles = 64;

/// Runs trace(begin, end) over ranges covering [0, tiles), one tile per task at the finest, on
/// the arena's threads, and returns when every range is done.
template <class Trace>
void trace_tiles_in(tbb::task_arena& arena, std::size_t tiles, const Trace& trace) {
  // Two addresses of their own for TSan's edges: caller -> tasks and tasks -> caller.
  [[maybe_unused]] char fork = 0, join = 0;
#if SPHRAY_RENDER_TSAN
  __tsan_release(&fork);
#endif
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tiles, 1), [&](const auto& range) {
#if SPHRAY_RENDER_TSAN
      __tsan_acquire(&fork);
#endif
      trace(range.begin(), range.end());
#if SPHRAY_RENDER_TSAN
      __tsan_release(&join);
#endif
    });
  });
#if SPHRAY_RENDER_TSAN
  __tsan_acquire(&join);
#endif
}

}  // namespace sphray::render
