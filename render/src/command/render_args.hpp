// The options of `sphray render` (and of `sphray-mpi render`, which takes those that make sense
// across processes): one definition, so that both commands name, check and document them alike.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "sphray/render/scene.hpp"

namespace sphray::render {

/// `--lookfrom`, `--lookat`, `--vup`, `--vfov`: each given one replaces that part of the scene's
/// camera (preset, scene file or particle file), the others stay the scene's.
struct CameraArgs {
  // Positions as written, in double: a scene traced in double keeps them (Scene::doubles).
  std::optional<Vec3d> lookfrom, lookat;
  std::optional<Vec3> vup;
  std::optional<float> vfov;
};

struct RenderArgs {
  std::string scene = "rtiow-final";
  std::optional<float> radius;       // the radius of a particle file's particles, if it has none
  std::optional<Material> material;  // every particle's (--material), particle files only
  CameraArgs camera;
  std::string mode = "normals";
  std::string accel = "auto";
  std::string precision = "float";
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
  bool precision = true;   // --precision
};

/// Registers the render options on a (sub)command, each with its check and its default shown.
void add_render_options(CLI::App& render, RenderArgs& args, RenderArgsScope scope = {});

/// Registers --lookfrom, --lookat, --vup and --vfov, each checked on its own (three finite
/// comma-separated numbers of at most 1e17 in magnitude; vfov in (0, 180)).
void add_camera_options(CLI::App& command, CameraArgs& camera);

/// scene's camera with the parts camera gives. Throws SceneError, naming the options given, if
/// the camera they make cannot be placed (lookfrom == lookat, vup parallel to the view).
void apply_camera(const CameraArgs& camera, Scene& scene);

/// The scene options the arguments give (--radius, --material).
SceneOptions scene_options(const RenderArgs& args);

/// --material's spelling: lambertian, metal[:FUZZ], glass[:IOR] (or dielectric[:IOR]), checked
/// as a scene file's material is (fuzz in [0, 1], ior > 0). Throws SceneError with "expected ...".
Material parse_material_option(std::string_view text);

/// --seed's check: every value of a std::uint64_t in decimal and nothing else (CLI11 would wrap
/// "-1" to 2^64 - 1 and take "1e23" as a saturated double).
CLI::Validator seed_range();

/// A number of seconds from 0 to 1e9, for the options that take one.
CLI::Validator seconds_validator();

}  // namespace sphray::render
