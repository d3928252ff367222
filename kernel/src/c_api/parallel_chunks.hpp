// Splits [0, count) into fixed chunks and runs them on up to `threads` threads: the calling
// thread and std::threads started for the call. Each element is written by exactly one chunk,
// so the result is the same whatever the thread count.
#pragma once

#include <cstddef>
#include <type_traits>

namespace sphray::c_api {

/// Rays per chunk: large enough that taking a chunk (one atomic increment) costs nothing next
/// to tracing it, small enough to balance a few hundred thousand rays over many cores.
inline constexpr std::size_t kParallelChunk = 4096;

/// The threads a call with this count and request uses: threads (SPHRAY_THREADS_ALL: one per
/// core; 0 counts as 1), no more than there are chunks, at least 1.
unsigned parallel_threads(std::size_t count, unsigned threads);

/// Calls chunk(context, worker, begin, end) for every chunk of [0, count), spread over
/// `workers` threads (parallel_threads()); worker < workers names the thread, so that a chunk
/// may use scratch space of its own. If the system refuses to start a thread, the threads
/// already running take its share. An exception chunk throws on any thread stops the work and
/// leaves the call on the calling thread (the first one thrown); so may std::bad_alloc.
void run_chunks(std::size_t count, unsigned workers,
                void (*chunk)(void*, unsigned, std::size_t, std::size_t), void* context);

/// run_chunks for a callable chunk(worker, begin, end); one worker calls it once, for the
/// whole range, on the calling thread.
template <class Chunk>
void parallel_chunks(std::size_t count, unsigned workers, Chunk&& chunk) {
  if (workers <= 1) {
    chunk(0u, std::size_t{0}, count);
    return;
  }
  run_chunks(
      count, workers,
      [](void* context, unsigned worker, std::size_t begin, std::size_t end) {
        (*static_cast<std::remove_reference_t<Chunk>*>(context))(worker, begin, end);
      },
      &chunk);
}

}  // namespace sphray::c_api
