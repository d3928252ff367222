// `sphray bench`: rays per second of every way sphray (and Embree, where the build has it)
// answers a scene's rays, each row checked against the scalar reference before it is timed.
#pragma once

#include <string>

#include "command/render_args.hpp"

namespace sphray::render::bench {

struct BenchArgs {
  std::string scene = "rtiow-final";
  std::string rays = "both";      // camera, random or both
  std::string query = "closest";  // closest or every-hit (bench_crossings.hpp)
  CameraArgs camera;              // the camera rays' camera, over the scene's
  int threads = 1;
  double seconds = 0.5;  // per row, shared among its repetitions
  int repetitions = 3;
  std::string json;    // Google Benchmark-style output file, or empty
  bool force = false;  // replace a read-only json file
  bool quiet = false;  // no progress on stderr
};

/// Runs the rows and prints them on stdout, one per line as each finishes. Returns the exit
/// status: 0, 2 for a scene that cannot be loaded (the message says where in the file) or a
/// JSON file that may not be replaced, 1 for a row that disagrees with the scalar reference or
/// a JSON file that cannot be written. The JSON file is checked before any row is timed.
int run_bench(const BenchArgs& args);

}  // namespace sphray::render::bench
