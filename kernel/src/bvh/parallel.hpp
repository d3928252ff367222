// The builder's fork-join loops: oneTBB when the build found it, plain loops otherwise.
//
// Under ThreadSanitizer each loop also tells the sanitizer the happens-before edges oneTBB makes
// (Debian's libtbb is not built with -fsanitize=thread, so its own atomics are invisible): what
// the caller did before the loop happens before every task, and every task before what the
// caller does after it. Without these TSan takes each task's first touch of the caller's data for
// a race, and its report path, run thousands of times, made a parallel build take over ten
// minutes. With them it checks the tasks against each other, which is the point.
#pragma once

#include <cstddef>

#if SPHRAY_HAS_TBB
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>
#endif

#if defined(__SANITIZE_THREAD__)
#define SPHRAY_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define SPHRAY_TSAN 1
#endif
#endif
#if SPHRAY_TSAN
#include <sanitizer/tsan_interface.h>
#endif

namespace sphray::detail {

/// A happens-before edge through one address (the object's own: empty, it still has a unique
/// one), for ThreadSanitizer, nothing otherwise: what a thread did before release() happens
/// before what any thread does after a later acquire().
class HappensBefore {
 public:
  void release() {
#if SPHRAY_TSAN
    __tsan_release(this);
#endif
  }
  void acquire() {
#if SPHRAY_TSAN
    __tsan_acquire(this);
#endif
  }
};

/// The two edges of a fork-join: caller -> each task, each task -> caller.
struct ForkJoin {
  HappensBefore fork, join;
};

/// Runs body(i) for i in [0, n), in parallel in chunks of grain.
template <class Body>
void parallel_for(std::size_t n, std::size_t grain, Body&& body) {
#if SPHRAY_HAS_TBB
  ForkJoin edges;
  edges.fork.release();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      edges.fork.acquire();
                      for (std::size_t i = r.begin(); i < r.end(); ++i)
                        body(i);
                      edges.join.release();
                    });
  edges.join.acquire();
#else
  (void)grain;
  for (std::size_t i = 0; i < n; ++i)
    body(i);
#endif
}

/// Combines fold(acc, i) for i in [begin, end) with join(a, b); in parallel, in chunks of
/// grain, from parallel_min on. join must be associative, commutative and exact (counts, min,
/// max): the result is then the same whatever the split.
template <class T, class Fold, class Join>
T reduce_range(std::size_t begin, std::size_t end, std::size_t parallel_min, std::size_t grain,
               const T& identity, Fold&& fold, Join&& join) {
#if SPHRAY_HAS_TBB
  if (end - begin >= parallel_min) {
    ForkJoin edges;
    edges.fork.release();
    const T result = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(begin, end, grain), identity,
        [&](const tbb::blocked_range<std::size_t>& r, T acc) {
          edges.fork.acquire();
          for (std::size_t i = r.begin(); i < r.end(); ++i)
            fold(acc, i);
          edges.join.release();
          return acc;
        },
        [&](T a, const T& b) {
          edges.fork.acquire();
          join(a, b);
          edges.join.release();
          return a;
        });
    edges.join.acquire();
    return result;
  }
#else
  (void)join;  // one thread: nothing to join
  (void)parallel_min;
  (void)grain;
#endif
  T acc = identity;
  for (std::size_t i = begin; i < end; ++i)
    fold(acc, i);
  return acc;
}

/// Tasks started with run() and waited for with wait(); without oneTBB run() runs the task.
class TaskGroup {
 public:
  template <class Task>
  void run(Task&& task) {
#if SPHRAY_HAS_TBB
    edges_.fork.release();
    group_.run([this, task] {
      edges_.fork.acquire();
      task();
      edges_.join.release();
    });
#else
    task();
#endif
  }
  void wait() {
#if SPHRAY_HAS_TBB
    group_.wait();
    edges_.join.acquire();
#endif
  }

 private:
#if SPHRAY_HAS_TBB
  tbb::task_group group_;
  ForkJoin edges_;
#endif
};

}  // namespace sphray::detail
