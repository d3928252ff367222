// The module's functions around the renderer: pinhole camera rays and whole images of the
// renderer's scenes, both through sphray::render's own code.
#pragma once

#include <pybind11/numpy.h>

#include <optional>
#include <string>

namespace sphray::python {

namespace py = pybind11;

/// (origins, directions), each (height, width, 3) float32: the renderer's pinhole camera at
/// eye looking at target, one ray through each pixel's centre, row 0 at the top, unit
/// directions. Throws ValueError for a camera the renderer cannot place.
py::tuple pinhole_rays(const py::handle& eye, const py::handle& target, const py::handle& up,
                       double vfov_deg, int width, int height);

struct RenderRequest {
  std::string scene;  // a preset name or a JSON scene file
  std::string mode = "normals";
  std::optional<int> width, height;  // unset: the scene's own size (one side: its aspect)
  int spp = 4;                       // the command's defaults
  std::uint64_t seed = 0;
  int threads = 0;
  std::string accel = "auto";
  int max_depth = 50;
  double time_limit = 0.0;  // path mode: seconds after which no sample is started (0: none)
};

/// The image sphray render would write, as uint8 (height, width, 3). Throws ValueError for an
/// unknown scene, mode or accel, or a size the renderer refuses; Interrupted when a signal
/// handler raised during the render.
py::array render(const RenderRequest& request);

}  // namespace sphray::python
