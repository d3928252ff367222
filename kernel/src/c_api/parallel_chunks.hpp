// Splits [0, count) into fixed chunks and runs them on up to `threads` threads: the calling
// thread and std::threads started for the call. Each element is written by exactly one chunk,
// so the result is the same whatever the thread count.
#pragma once

#include <cstddef>

namespace sphray::c_api {

/// Rays per chunk: large enough that taking a chunk (one atomic increment) costs nothing next
/// to tracing it, small enough to balance a few hundred thousand rays over many cores.
inline constexpr std::size_t kParallelChunk = 4096;

/// The threads a call with this count and request uses: threads (0: one per core), no more
/// than there are chunks, at least 1.
unsigned parallel_threads(std::size_t count, unsigned threads);

/// Calls chunk(begin, end) for every chunk of [0, count), spread over `workers` threads
/// (parallel_threads()). chunk must not throw. If the system refuses to start a thread, the
/// threads already running take its share. Throws std::bad_alloc.
void run_chunks(std::size_t count, unsigned workers, void (*chunk)(void*, std::size_t, std::size_t),
                void* context);

/// run_chunks for a callable.
template <class Chunk>
void parallel_chunks(std::size_t count, unsigned threads, Chunk&& chunk) {
  run_chunks(
      count, parallel_threads(count, threads),
      [](void* context, std::size_t begin, std::size_t end) {
        (*static_cast<Chunk*>(context))(begin, end);
      },
      &chunk);
}

}  // namespace sphray::c_api
