#include "camera.hpp"

#include <cstring>

#include "arrays.hpp"
#include "interruption.hpp"
#include "ray_batches.hpp"
#include "sphray/render/camera.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::python {
namespace {

Vec3 as_vec3(const char* what, const py::handle& obj) {
  py::array a = as_real_array(what, obj);
  if (a.ndim() != 1 || a.shape(0) != 3) {
    throw py::value_error(std::string(what) + ": expected shape (3,), got " + shape_text(a));
  }
  const auto f = converted<double, py::array::c_style>(what, a);
  const double* v = f.data();
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

// The command's rule (render/tools/sphray.cpp): one side given keeps the scene's aspect.
int other_side(int given, int scene_given, int scene_other) {
  const long long side = static_cast<long long>(given) * scene_other / scene_given;
  return static_cast<int>(std::max(1LL, side));
}

render::RenderOptions render_options(const RenderRequest& r, const render::Scene& scene) {
  render::RenderOptions options;
  const auto mode = render::parse_mode(r.mode);
  if (!mode) throw py::value_error("mode: unknown mode '" + r.mode + "'");
  const auto accel = render::parse_accel(r.accel);
  if (!accel)
    throw py::value_error("accel: expected 'auto', 'bvh' or 'brute', got '" + r.accel + "'");
  options.mode = *mode;
  options.accel = *accel;
  options.width = r.width    ? *r.width
                  : r.height ? other_side(*r.height, scene.height, scene.width)
                             : scene.width;
  options.height = r.height  ? *r.height
                   : r.width ? other_side(*r.width, scene.width, scene.height)
                             : scene.height;
  if (options.width < 1 || options.height < 1 || options.width > render::kMaxImageSide ||
      options.height > render::kMaxImageSide) {
    throw py::value_error("render: expected width and height from 1 to " +
                          std::to_string(render::kMaxImageSide) + ", got " +
                          std::to_string(options.width) + "x" + std::to_string(options.height));
  }
  options.spp = r.spp;
  options.seed = r.seed;
  options.threads = r.threads;
  options.max_depth = r.max_depth;
  options.time_limit = r.time_limit;
  return options;
}

}  // namespace

py::tuple pinhole_rays(const py::handle& eye, const py::handle& target, const py::handle& up,
                       double vfov_deg, int width, int height) {
  render::CameraSpec spec;
  spec.lookfrom = as_vec3("eye", eye);
  spec.lookat = as_vec3("target", target);
  spec.vup = as_vec3("up", up);
  spec.vfov = static_cast<float>(vfov_deg);
  std::optional<render::Camera> camera;
  try {
    camera.emplace(spec, width, height);
  } catch (const render::SceneError& e) {
    throw py::value_error(e.what());
  }
  if (width > render::kMaxImageSide || height > render::kMaxImageSide) {
    throw py::value_error("pinhole_rays: width and height must be at most " +
                          std::to_string(render::kMaxImageSide) + ", got " + std::to_string(width) +
                          "x" + std::to_string(height));
  }
  auto origins = new_array<float>({height, width}, {3});
  auto directions = new_array<float>({height, width}, {3});
  float* o = origins.mutable_data();
  float* d = directions.mutable_data();
  const std::size_t w = static_cast<std::size_t>(width);
  const std::size_t count = w * static_cast<std::size_t>(height);
  {
    py::gil_scoped_release release;
    for_each_chunk(count, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const float px = static_cast<float>(i % w) + 0.5f;
        const float py = static_cast<float>(i / w) + 0.5f;
        const Ray ray = camera->ray(px, py);
        const Vec3 dir = normalize(ray.dir);
        for (int k = 0; k < 3; ++k) {
          o[3 * i + k] = ray.origin[k];
          d[3 * i + k] = dir[k];
        }
      }
    });
  }
  return py::make_tuple(origins, directions);
}

py::array render(const RenderRequest& request) {
  render::Scene scene;
  render::RenderOptions options;
  try {
    scene = render::load_scene_or_preset(request.scene);
    options = render_options(request, scene);
  } catch (const render::SceneError& e) {
    throw py::value_error(e.what());
  }
  render::Image image;
  {
    py::gil_scoped_release release;
    try {
      // The renderer reports each finished tile: there the calling thread answers a Ctrl-C.
      Interruption interruption;
      image = render::render(
          scene, options,
          [&](std::size_t, std::size_t, const render::RayCounts&) { interruption.check(); });
    } catch (const render::SceneError& e) {
      throw std::invalid_argument(e.what());  // ValueError, raised once the GIL is back
    }
  }
  auto out = new_array<std::uint8_t>({image.height, image.width}, {3});
  std::memcpy(out.mutable_data(), image.rgb.data(), image.rgb.size());
  return out;
}

}  // namespace sphray::python
