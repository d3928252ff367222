// The module's functions around the renderer: pinhole camera rays and whole images of the
// renderer's scenes, both through sphray::render's own code.
#pragma once

#include <pybind11/numpy.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sphray/sphray.hpp"

namespace sphray::python {

namespace py = pybind11;

/// (origins, directions), each (height, width, 3) float32: the renderer's pinhole camera at
/// eye looking at target, one ray through each pixel's centre, row 0 at the top, unit
/// directions. Throws ValueError for a camera the renderer cannot place.
py::tuple pinhole_rays(const py::handle& eye, const py::handle& target, const py::handle& up,
                       double vfov_deg, int width, int height);

struct RenderRequest {
  std::string scene;  // a preset name or a JSON scene file, unless spheres is set
  std::string mode = "normals";
  std::optional<int> width, height;  // unset: the scene's own size (one side: its aspect)
  int spp = 4;                       // the command's defaults
  std::uint64_t seed = 0;
  int threads = 0;
  std::string accel = "auto";
  int max_depth = 50;
  double time_limit = 0.0;  // path mode: seconds after which no sample is started (0: none)
  std::optional<SphereSoA> spheres;  // the caller's own spheres, rendered instead of scene
  std::vector<Vec3> colors;          // with spheres: one per sphere, or none (grey)
  // With spheres: the distinct JSON materials, each with the first sphere that has it (for
  // messages), and sphere i's index among them (empty: one material for every sphere).
  std::vector<std::pair<std::string, std::size_t>> materials;
  std::vector<std::uint32_t> material_of;
  std::optional<std::string> camera;  // a camera object as scene files write it (JSON)
  bool linear = false;                // path mode: the linear radiance as float32, not bytes
};

/// colors as one colour per sphere of count: an (count, 3) array of values in [0, 1]. Throws
/// ValueError for another shape or a value out of range, TypeError for a dtype that is not real.
std::vector<Vec3> colors_of(const py::handle& colors, std::size_t count);

/// The image sphray render would write, as uint8 (height, width, 3), or with request.linear
/// path mode's radiance as float32. Throws ValueError for an unknown scene, mode or accel, a
/// camera or size the renderer refuses, or linear outside path mode; Interrupted when a signal
/// handler raised during the render.
py::array render(const RenderRequest& request);

}  // namespace sphray::python
