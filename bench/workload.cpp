#include "workload.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <random>

#include "bench/bench_rays.hpp"  // render/src/bench: the rays `sphray bench` traces
#include "sphray/render/camera.hpp"
#include "sphray/render/path_tracer.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::bench {
namespace {

// random:128 and random:256 sit where the BVH overtakes brute force (the renderer's switch).
constexpr std::array<std::string_view, 11> kScenes = {
    "single",     "three",      "rtiow-final", "random:8",     "random:64",     "random:128",
    "random:256", "random:512", "random:4096", "random:65536", "random:1048576"};

// Row-major camera rays of a side x side image: what the renderer traces for that image.
std::vector<Ray> camera_rays(const render::CameraSpec& spec, int side) {
  const render::Camera camera(spec, side, side);
  std::vector<Ray> rays;
  rays.reserve(static_cast<std::size_t>(side) * side);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
      rays.push_back(camera.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f));
  return rays;
}

int image_side(std::size_t rays) {
  return static_cast<int>(std::lround(std::sqrt(static_cast<double>(rays))));
}

// kSampleRays rays drawn without replacement, so the sample spans the whole image.
std::vector<Ray> draw_sample(const std::vector<Ray>& rays) {
  if (rays.size() <= kSampleRays) return rays;
  std::vector<Ray> sample;
  std::sample(rays.begin(), rays.end(), std::back_inserter(sample), kSampleRays,
              std::mt19937(12345));
  return sample;
}

// The rays a path-traced 512 x 512 frame of the scene (1 sample, the book's depth) traces at
// bounces 1 to 3, in the order the renderer traces them: per tile, one wavefront per bounce.
std::vector<Ray> bounce_rays(const render::Scene& scene) {
  render::RenderOptions options;
  options.mode = render::Mode::path;
  options.width = 512;
  options.height = 512;
  options.spp = 1;
  return render::record_path_rays(scene, options, 1, 3);
}

std::vector<Hit> reference_hits(SphereView view, const std::vector<Ray>& rays) {
  std::vector<Hit> hits(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i)
    hits[i] = scalar::intersect(view, rays[i]);
  return hits;
}

std::unique_ptr<Workload> make_workload(std::string_view scene, RayKind kind) {
  auto w = std::make_unique<Workload>();
  w->scene = std::string(scene);
  w->kind = kind;
  render::Scene preset = render::make_preset(w->scene);
  // Recorded before the spheres move out of the scene (the path tracer needs them).
  std::vector<Ray> bounces = kind == RayKind::bounce ? bounce_rays(preset) : std::vector<Ray>{};
  w->spheres = std::move(preset.spheres);
  const std::size_t brute = brute_ray_count(w->spheres.size());
  if (kind == RayKind::coherent) {
    w->rays = camera_rays(preset.camera, image_side(kFullRays));
    w->brute_rays = brute == kFullRays ? w->rays : camera_rays(preset.camera, image_side(brute));
  } else if (kind == RayKind::bounce) {
    w->rays = std::move(bounces);
    w->brute_rays = render::bench::spread(w->rays, brute);
  } else {
    w->rays = random_rays(sphere_box(w->spheres), kFullRays, 2024, 0.0f);
    w->brute_rays.assign(w->rays.begin(), w->rays.begin() + static_cast<std::ptrdiff_t>(brute));
  }
  w->sample = draw_sample(w->brute_rays);
  w->expected = reference_hits(w->view(), w->sample);
  return w;
}

}  // namespace

std::string_view ray_kind_name(RayKind kind) {
  switch (kind) {
    case RayKind::coherent:
      return "coherent";
    case RayKind::incoherent:
      return "incoherent";
    case RayKind::bounce:
      return "bounce";
  }
  return "";
}

std::span<const RayKind> ray_kinds(std::string_view scene) {
  static constexpr std::array<RayKind, 3> kWithBounces = {RayKind::coherent, RayKind::incoherent,
                                                          RayKind::bounce};
  if (scene == "rtiow-final" || scene == "random:65536") return kWithBounces;
  return std::span(kWithBounces).first(2);
}

std::span<const std::string_view> scene_names() {
  return kScenes;
}

const Workload& workload(std::string_view scene, RayKind kind) {
  static std::unique_ptr<Workload> current;
  if (!current || current->scene != scene || current->kind != kind) {
    current.reset();  // free the old one first: two million-sphere workloads need not coexist
    current = make_workload(scene, kind);
  }
  return *current;
}

std::size_t brute_ray_count(std::size_t spheres) {
  std::size_t rays = kFullRays;
  while (rays > kMinBruteRays && rays * spheres > kBruteTestBudget)
    rays /= 4;
  return rays;
}

}  // namespace sphray::bench
