#include "bench/random_rays.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace sphray::render::bench {

Box sphere_box(const SphereSoA& spheres) {
  std::vector<float> radii(spheres.size());
  for (std::uint32_t i = 0; i < spheres.size(); ++i)
    radii[i] = spheres.radius(i);
  if (radii.empty()) return {{-1, -1, -1}, {1, 1, 1}};
  const auto middle = radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2);
  std::nth_element(radii.begin(), middle, radii.end());
  const float limit = 10.0f * *middle;
  Box box{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
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

std::vector<Ray> random_rays(const Box& box, std::size_t count, unsigned seed, float tmin) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  auto lerp = [&](float lo, float hi) { return lo + unit(rng) * (hi - lo); };
  std::vector<Ray> rays(count);
  for (Ray& ray : rays) {
    ray.origin = {lerp(box.lo.x, box.hi.x), lerp(box.lo.y, box.hi.y), lerp(box.lo.z, box.hi.z)};
    // A normalised Gaussian vector is uniform on the sphere; redraw the (vanishingly rare)
    // near-zero ones rather than normalise noise.
    Vec3 d;
    do {
      d = {gauss(rng), gauss(rng), gauss(rng)};
    } while (length_squared(d) < 1e-6f);
    ray.dir = normalize(d);
    ray.tmin = tmin;
  }
  return rays;
}

}  // namespace sphray::render::bench
