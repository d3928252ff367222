// `sphray bench --json FILE`: the results in Google Benchmark's JSON layout (a context object
// and a benchmarks array whose entries have name, iterations, real_time, cpu_time, time_unit and
// items_per_second), so that the tools that read that format read these. As Google Benchmark
// writes --benchmark_repetitions: one "iteration" entry per repetition, then "aggregate" entries
// (mean, median, stddev, min, max) named NAME_mean and so on.
#pragma once

#include <string>
#include <vector>

#include "bench/bench_timing.hpp"

namespace sphray::render::bench {

struct Context {
  std::string scene;
  std::size_t spheres = 0;
  int threads = 1;
  double seconds_per_row = 0.0;
  int repetitions = 1;
  std::vector<double> load_average;  // 1, 5 and 15 minutes when the run started, if known
};

struct Result {
  std::string name;   // scene/rays/row/threads:N, the row's spaces as dashes
  std::string label;  // "dispatched" for what sphray::intersect takes, else empty
  RowTiming timing;
  std::string skipped;  // why the row was not timed (then timing is empty), or empty
};

/// The JSON text.
std::string results_json(const Context& context, const std::vector<Result>& results);

}  // namespace sphray::render::bench
