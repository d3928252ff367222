// The options of `sphray render` (and of `sphray-mpi render`, which takes those that make sense
// across processes): one definition, so that both commands name, check and document them alike.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>

namespace sphray::render {

struct RenderArgs {
  std::string scene = "rtiow-final";
  std::optional<float> radius;  // the radius of a particle file's particles, if it has none
  std::string mode = "normals";
  std::string accel = "auto";
  int width = 0, height = 0;  // 0: the scene's own size
  int spp = 4;
  int threads = 0;
  std::uint64_t seed = 0;
  int max_depth = 50;
  double time_limit = 0.0;
  std::string output = "sphray.png";
  bool quiet = false;
  bool force = false;  // replace a read-only output
};

/// Which options a command takes beyond the image's own (scene, mode, size, samples, seed,
/// depth, output, quiet): those of one process's threads, clock and files.
struct RenderArgsScope {
  bool threads = true;     // --threads
  bool time_limit = true;  // --time-limit
  bool accel = true;       // --accel
  bool force = true;       // --force
};

/// Registers the render options on a (sub)command, each with its check and its default shown.
void add_render_options(CLI::App& render, RenderArgs& args, RenderArgsScope scope = {});

/// --seed's check: every value of a std::uint64_t in decimal and nothing else (CLI11 would wrap
/// "-1" to 2^64 - 1 and take "1e23" as a saturated double).
CLI::Validator seed_range();

/// A number of seconds from 0 to 1e9, for the options that take one.
CLI::Validator seconds_validator();

}  // namespace sphray::render
