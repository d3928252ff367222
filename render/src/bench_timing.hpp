// One row of `sphray bench`: checked against the scalar reference, then timed.
#pragma once

#include <cstddef>
#include <string>

#include "bench_rays.hpp"
#include "bench_rows.hpp"

namespace sphray::render::bench {

struct Timing {
  /// Empty if every sampled hit agrees; otherwise the first disagreement, and nothing is timed.
  std::string mismatch;
  std::size_t passes = 0;
  std::size_t rays_per_pass = 0;
  double seconds = 0.0;      // wall time of all passes
  double cpu_seconds = 0.0;  // CPU time of the process over them (all threads)

  double rays_per_second() const {
    return seconds > 0 ? static_cast<double>(passes * rays_per_pass) / seconds : 0.0;
  }
};

/// Checks trace against set.expected on set.sample (bit for bit for an exact row; otherwise t
/// within 1e-3 of max(1, |t|) and the same sphere, or another at that t), then traces the row's
/// rays on `threads` threads, pass after pass, for at least `seconds` (one pass at least).
Timing time_row(const Row& row, const Trace& trace, const RaySet& set, int threads, double seconds);

}  // namespace sphray::render::bench
