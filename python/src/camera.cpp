#include "camera.hpp"

#include <cstdio>
#include <cstring>

#include "arrays.hpp"
#include "interruption.hpp"
#include "ray_batches.hpp"
#include "results.hpp"
#include "sphray/render/camera.hpp"
#include "sphray/render/path_tracer.hpp"
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

// With no camera given, the caller's spheres seen whole: from +z, looking down -z at the centre
// of their bounding box, far enough that the box's bounding sphere fits the vertical field of
// view (the horizontal one is wider at the default 16:9). Spheres the kernel never hits (NaN
// or infinite fields, radius <= 0) are left out; with none left, the default camera.
render::CameraSpec framing(const SphereSoA& spheres) {
  render::CameraSpec camera;
  camera.vfov = 40.0f;
  const SphereView v = spheres.view();
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i = 0; i < v.count; ++i) {
    const float c[3] = {v.cx[i], v.cy[i], v.cz[i]}, r = v.radius[i];
    if (!(std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]) && r > 0.0f &&
          std::isfinite(r)))
      continue;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], c[k] - r);
      hi[k] = std::max(hi[k], c[k] + r);
    }
  }
  if (!(lo[0] <= hi[0])) return camera;
  const Vec3 centre{0.5f * (lo[0] + hi[0]), 0.5f * (lo[1] + hi[1]), 0.5f * (lo[2] + hi[2])};
  const float half = 0.5f * length(Vec3{hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const float distance = 1.1f * half / std::sin(0.5f * camera.vfov * 3.14159265f / 180.0f);
  camera.lookat = centre;
  camera.lookfrom = centre + Vec3{0.0f, 0.0f, distance};
  camera.focus_dist = distance;
  return camera;
}

// The caller's materials, each distinct one parsed once as a scene file's sphere would hold it
// (the same checks and defaults: a material without an albedo takes the sphere's colour, a
// sphere without a colour shows its material's albedo in the other modes).
void add_materials(render::Scene& scene, const RenderRequest& r) {
  std::vector<render::MaterialEntry> entries;
  for (const auto& [text, first] : r.materials) {
    const std::string source =
        r.material_of.empty() ? "materials" : "materials[" + std::to_string(first) + "]";
    entries.push_back(render::parse_material(text, source));
  }
  const std::size_t n = scene.spheres.size();
  scene.materials.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const render::MaterialEntry& entry = entries[r.material_of.empty() ? 0 : r.material_of[i]];
    render::Material& material = scene.materials[i];
    material = entry.material;
    if (!entry.albedo_given) material.albedo = scene.colors[i];
    if (r.colors.empty()) scene.colors[i] = material.albedo;
  }
}

render::Scene scene_of(const RenderRequest& r) {
  render::Scene scene;
  if (r.spheres) {
    scene.name = "spheres";
    scene.spheres = *r.spheres;
    scene.colors = r.colors;
    scene.colors.resize(scene.spheres.size(), Vec3{0.5f, 0.5f, 0.5f});  // scene files' grey
    scene.camera = framing(scene.spheres);
    if (!r.materials.empty()) add_materials(scene, r);
  } else {
    scene = render::load_scene_or_preset(r.scene);
  }
  // The camera parsed as a scene file's, with the same checks and messages.
  if (r.camera) {
    scene.camera =
        render::parse_scene("{\"camera\": " + *r.camera + ", \"spheres\": []}", "camera").camera;
  }
  return scene;
}

py::array linear_image(const std::vector<Vec3>& radiance, int width, int height) {
  auto out = new_array<float>({height, width}, {3});
  float* p = out.mutable_data();
  for (const Vec3& c : radiance) {
    *p++ = c.x;
    *p++ = c.y;
    *p++ = c.z;
  }
  return out;
}

}  // namespace

std::vector<Vec3> colors_of(const py::handle& colors, std::size_t count) {
  const py::array a = as_real_array("colors", colors);
  if (a.ndim() != 2 || a.shape(0) != static_cast<py::ssize_t>(count) || a.shape(1) != 3) {
    throw py::value_error("colors: expected the shape (" + std::to_string(count) +
                          ", 3), one per sphere, got " + shape_text(a));
  }
  const auto f = converted<float, py::array::c_style>("colors", a);
  std::vector<Vec3> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    for (int k = 0; k < 3; ++k) {
      const float c = f.data()[3 * i + static_cast<std::size_t>(k)];
      if (!(c >= 0.0f && c <= 1.0f)) {
        throw py::value_error("colors[" + std::to_string(i) + "]: expected components in [0, 1]");
      }
    }
    out[i] = {f.data()[3 * i], f.data()[3 * i + 1], f.data()[3 * i + 2]};
  }
  return out;
}

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
  return make_result(Result::rays, {origins, directions});
}

py::array render(const RenderRequest& request) {
  render::Scene scene;
  render::RenderOptions options;
  try {
    scene = scene_of(request);
    options = render_options(request, scene);
  } catch (const render::SceneError& e) {
    throw py::value_error(e.what());
  }
  if (request.linear && options.mode != render::Mode::path) {
    throw py::value_error("linear: only path mode has a linear image (its radiance); got mode '" +
                          request.mode + "'");
  }
  render::Image image;
  std::vector<Vec3> radiance;
  {
    py::gil_scoped_release release;
    try {
      // The renderer reports each finished tile: there the calling thread answers a Ctrl-C.
      Interruption interruption;
      const render::Progress progress = [&](std::size_t, std::size_t, const render::RayCounts&) {
        interruption.check();
      };
      if (request.linear) {
        radiance = render::render_radiance(scene, options, progress);
      } else {
        image = render::render(scene, options, progress);
      }
    } catch (const render::SceneError& e) {
      throw std::invalid_argument(e.what());  // ValueError, raised once the GIL is back
    }
  }
  if (request.linear) return linear_image(radiance, options.width, options.height);
  auto out = new_array<std::uint8_t>({image.height, image.width}, {3});
  std::memcpy(out.mutable_data(), image.rgb.data(), image.rgb.size());
  return out;
}

}  // namespace sphray::python
