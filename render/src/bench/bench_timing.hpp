// One row of `sphray bench`: checked against the scalar reference, then timed.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "bench/bench_rays.hpp"
#include "bench/bench_rows.hpp"

namespace sphray::render::bench {

/// One repetition: passes over the row's rays for at least its share of the row's seconds.
struct Timing {
  std::size_t passes = 0;
  std::size_t rays_per_pass = 0;
  double seconds = 0.0;      // wall time of all passes
  double cpu_seconds = 0.0;  // CPU time of the process over them (all threads)

  double rays_per_second() const {
    return seconds > 0 ? static_cast<double>(passes * rays_per_pass) / seconds : 0.0;
  }
};

/// A row's repetitions.
struct RowTiming {
  /// Empty if every sampled hit agrees; otherwise the first disagreement, and nothing is timed.
  std::string mismatch;
  std::vector<Timing> repetitions;
  int threads = 1;

  /// Rays per second by wall time: the median repetition's, the slowest's and the fastest's.
  double median_rate() const;
  double min_rate() const;
  double max_rate() const;
  /// The median repetition's rays per second had every thread run all the time: rays over the
  /// CPU time of the process divided by the threads (the rate a busy machine hides).
  double median_cpu_rate() const;
  /// The CPU time over wall time times threads of all repetitions: 1 when the threads had their
  /// cores all the time, less when other work took turns on them.
  double cpu_share() const;
};

/// Answers rays [begin, end) of a pass; called on several threads at once.
using Answer = std::function<void(std::size_t begin, std::size_t end)>;

/// Times `repetitions` repetitions of passes over rays rays on `threads` threads, each pass
/// after pass for at least seconds / repetitions (one pass at least), after one pass to warm up.
RowTiming time_passes(std::size_t rays, const Answer& answer, int threads, double seconds,
                      int repetitions);

/// Checks trace against set.expected on set.sample (bit for bit for an exact row; otherwise t
/// within 1e-3 of max(1, |t|) and the same sphere, or another at that t), traces the row's rays
/// once to warm up, then times `repetitions` repetitions on `threads` threads, each pass after
/// pass for at least seconds / repetitions (one pass at least).
RowTiming time_row(const Row& row, const Trace& trace, const RaySet& set, int threads,
                   double seconds, int repetitions);

}  // namespace sphray::render::bench
