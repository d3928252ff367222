// Splitting a ray stream across threads: the caller's job, not the kernel's (the queries are
// thread-safe and never allocate). oneTBB arenas fix the thread count per benchmark.
#pragma once

#include <cstddef>
#include <functional>

namespace sphray::bench {

/// The threads "all" means: what oneTBB would use by default on this machine.
int all_threads();

/// Calls chunk(begin, end) over [0, count) split into chunks, on exactly `threads` threads
/// (the calling thread among them).
void parallel_chunks(int threads, std::size_t count,
                     const std::function<void(std::size_t, std::size_t)>& chunk);

/// Runs work on exactly `threads` threads: oneTBB parallelism inside it (Embree's scene
/// build, say) stays within them.
void run_on_threads(int threads, const std::function<void()>& work);

}  // namespace sphray::bench
