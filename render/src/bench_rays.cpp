#include "bench_rays.hpp"

#include <algorithm>
#include <cmath>
#include <random>

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

struct Box {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
};

// The bounds of the spheres, leaving out those over 10 times the median radius: a ground sphere
// of radius 1000 under spheres of radius 1 would otherwise put nearly every origin far from
// anything.
Box sphere_box(const SphereSoA& spheres) {
  std::vector<float> radii(spheres.size());
  for (std::uint32_t i = 0; i < spheres.size(); ++i)
    radii[i] = spheres.radius(i);
  const auto middle = radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2);
  std::nth_element(radii.begin(), middle, radii.end());
  const float limit = 10.0f * *middle;
  Box box;
  for (std::uint32_t i = 0; i < spheres.size(); ++i) {
    const float r = spheres.radius(i);
    if (!(r <= limit)) continue;
    const Vec3 c = spheres.center(i);
    box.lo = {std::min(box.lo.x, c.x - r), std::min(box.lo.y, c.y - r),
              std::min(box.lo.z, c.z - r)};
    box.hi = {std::max(box.hi.x, c.x + r), std::max(box.hi.y, c.y + r),
              std::max(box.hi.z, c.z + r)};
  }
  if (!(box.lo.x <= box.hi.x)) box = {{-1, -1, -1}, {1, 1, 1}};  // no finite sphere
  return box;
}

std::vector<Ray> random_rays(const SphereSoA& spheres) {
  const Box box = sphere_box(spheres);
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  auto lerp = [&](float lo, float hi) { return lo + unit(rng) * (hi - lo); };
  std::vector<Ray> rays(kRandomRays);
  for (Ray& ray : rays) {
    ray.origin = {lerp(box.lo.x, box.hi.x), lerp(box.lo.y, box.hi.y), lerp(box.lo.z, box.hi.z)};
    Vec3 d;
    do {  // a normalised Gaussian vector is uniform on the sphere
      d = {gauss(rng), gauss(rng), gauss(rng)};
    } while (length_squared(d) < 1e-6f);
    ray.dir = normalize(d);
    ray.tmin = 1e-3f;
  }
  return rays;
}

// count rays spread evenly over rays (the whole image, not its top rows).
std::vector<Ray> spread(const std::vector<Ray>& rays, std::size_t count) {
  if (count >= rays.size()) return rays;
  std::vector<Ray> out(count);
  for (std::size_t i = 0; i < count; ++i)
    out[i] = rays[i * rays.size() / count];
  return out;
}

std::size_t brute_ray_count(std::size_t rays, std::size_t spheres) {
  const std::size_t budget = kBruteTestBudget / std::max<std::size_t>(1, spheres);
  return std::min(rays, std::max(kMinBruteRays, budget));
}

}  // namespace

const char* ray_kind_name(RayKind kind) {
  return kind == RayKind::camera ? "camera" : "random";
}

RaySet make_ray_set(const Scene& scene, RayKind kind) {
  RaySet set{kind, {}, {}, {}, {}, {}};
  if (kind == RayKind::camera) {
    set.rays = camera_rays(scene);
    set.description =
        std::to_string(scene.width) + "x" + std::to_string(scene.height) + " camera image";
  } else {
    set.rays = random_rays(scene.spheres);
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
