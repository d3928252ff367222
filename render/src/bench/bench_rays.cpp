#include "bench/bench_rays.hpp"

#include <algorithm>

#include "bench/random_rays.hpp"
#include "sphray/render/camera.hpp"

namespace sphray::render::bench {
namespace {

std::vector<Ray> camera_rays(const Scene& scene) {
  const Camera camera(scene.camera, scene.width, scene.height);
  std::vector<Ray> rays;
  rays.reserve(static_cast<std::size_t>(scene.width) * static_cast<std::size_t>(scene.height));
  for (int y = 0; y < scene.height; ++y)
    for (int x = 0; x < scene.width; ++x)
      rays.push_back(camera.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f));
  return rays;
}

std::size_t brute_ray_count(std::size_t rays, std::size_t spheres) {
  const std::size_t budget = kBruteTestBudget / std::max<std::size_t>(1, spheres);
  return std::min(rays, std::max(kMinBruteRays, budget));
}

}  // namespace

const char* ray_kind_name(RayKind kind) {
  return kind == RayKind::camera ? "camera" : "random";
}

std::vector<Ray> spread(const std::vector<Ray>& rays, std::size_t count) {
  if (count >= rays.size()) return rays;
  std::vector<Ray> out(count);
  for (std::size_t i = 0; i < count; ++i)
    out[i] = rays[i * rays.size() / count];
  return out;
}

RaySet make_ray_set(const Scene& scene, RayKind kind) {
  RaySet set{kind, {}, {}, {}, {}, {}};
  if (kind == RayKind::camera) {
    set.rays = camera_rays(scene);
    set.description =
        std::to_string(scene.width) + "x" + std::to_string(scene.height) + " camera image";
  } else {
    set.rays = random_rays(sphere_box(scene.spheres), kRandomRays, 2024, 1e-3f);
    set.description = std::to_string(set.rays.size()) + " random rays";
  }
  set.brute_rays = spread(set.rays, brute_ray_count(set.rays.size(), scene.spheres.size()));
  set.sample = spread(set.brute_rays, kSampleRays);
  set.expected.resize(set.sample.size());
  for (std::size_t i = 0; i < set.sample.size(); ++i)
    set.expected[i] = scalar::intersect(scene.spheres.view(), set.sample[i]);
  return set;
}

}  // namespace sphray::render::bench
