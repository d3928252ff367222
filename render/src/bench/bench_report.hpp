// The words `sphray bench` prints around its rates: how long the run should take, whether the
// machine is too busy for the wall-clock rates to mean much, and which call to use.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace sphray::render::bench {

/// The run's expected length before it starts: every timed row's seconds. Its warm-up pass, its
/// check, a tree's build and the rays' making come on top; they are short beside it unless a
/// pass over the rays takes longer than a repetition's share of the seconds.
double estimate_seconds(std::size_t timed_rows, double seconds_per_row);

/// A warning when the load average over the last minute says other work takes turns on the
/// cores this run's threads need (more than cores - threads + 0.5 runnable), else empty.
std::string load_warning(double load_1min, unsigned cores, int threads);

/// One row's rates, for the closing recommendation.
struct Measured {
  std::string name;         // "avx512 stream"
  bool dispatched = false;  // what sphray's calls take by default (the rows marked *)
  bool brute_force = false;
  bool stream = false;  // a stream call: on the tree, or on the spheres if brute force
  bool sphray = true;   // false for another library's row
  double median = 0, min = 0, max = 0;  // rays per second by wall time
};

/// Which of sphray's calls is fastest for this kind of rays ("camera", "random"): the stream
/// call, the per-ray call on the default tree or brute force, each other one as how much slower
/// and whether within the spread of the repetitions; and a tree of another instruction set where
/// it was faster beyond the spread. Empty if no sphray row was timed.
std::string recommendation(const std::vector<Measured>& rows, const std::string& kind);

}  // namespace sphray::render::bench
