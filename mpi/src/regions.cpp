#include "sphray/mpi/regions.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace sphray::mpi {

namespace {

// The padded box around spheres.cx[index(i)] ... for i in [0, n): region_box's rule.
template <class Index>
RegionBox padded_box(SphereView spheres, std::size_t n, Index&& index) {
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::numeric_limits<double>::infinity();
    hi[k] = -std::numeric_limits<double>::infinity();
  }
  bool empty = true;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t s = index(i);
    const double c[3] = {spheres.cx[s], spheres.cy[s], spheres.cz[s]};
    const double r = spheres.radius[s];
    if (!(r > 0) || !std::isfinite(r) || !std::isfinite(c[0]) || !std::isfinite(c[1]) ||
        !std::isfinite(c[2]))
      continue;
    empty = false;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], c[k] - r);
      hi[k] = std::max(hi[k], c[k] + r);
    }
  }
  RegionBox box;
  if (empty) return box;
  double scale = 0;
  for (int k = 0; k < 3; ++k)
    scale = std::max({scale, std::abs(lo[k]), std::abs(hi[k])});
  const double pad = kRegionSlack * scale + std::numeric_limits<float>::min();
  for (int k = 0; k < 3; ++k) {
    box.lo[k] = static_cast<float>(lo[k] - pad);  // the padding dwarfs the rounding
    box.hi[k] = static_cast<float>(hi[k] + pad);
  }
  box.empty = false;
  return box;
}

}  // namespace

RegionBox region_box(SphereView spheres) {
  return padded_box(spheres, spheres.count, [](std::size_t i) { return i; });
}

RegionBox region_box(SphereView spheres, std::span<const std::uint32_t> ids) {
  return padded_box(spheres, ids.size(), [ids](std::size_t i) { return std::size_t{ids[i]}; });
}

namespace {

// The ray's origin and direction as arrays, and whether the ray can be routed at all (finite
// origin and direction, a direction not zero, tmin not NaN).
struct RayParts {
  float o[3], d[3];
  bool valid;
  float scale;  // the largest |o| over the largest |d|: the origin's size in units of t
};

RayParts parts_of(const Ray& ray) {
  RayParts p{{ray.origin.x, ray.origin.y, ray.origin.z},
             {ray.dir.x, ray.dir.y, ray.dir.z},
             !std::isnan(ray.tmin),
             0.0f};
  float size = 0, speed = 0;
  for (int k = 0; k < 3; ++k) {
    p.valid = p.valid && std::isfinite(p.o[k]) && std::isfinite(p.d[k]);
    size = std::max(size, std::abs(p.o[k]));
    speed = std::max(speed, std::abs(p.d[k]));
  }
  p.valid = p.valid && speed > 0;
  p.scale = p.valid ? size / speed : 0.0f;
  return p;
}

// The kernel rounds t relative to the origin's and the sphere's size (the latter is in the
// box's padding): the bound is widened by the same relative slack, which also covers the
// rounding of the slab test.
float widened(float bound, float scale) {
  return bound + kRegionSlack * (std::abs(bound) + scale);
}

}  // namespace

RegionSteps next_regions(std::span<const RegionBox> regions, const Ray& ray, float bound,
                         RegionKey after) {
  RegionSteps steps;
  const RayParts p = parts_of(ray);
  if (!p.valid || std::isnan(bound)) return steps;
  const float t1 = widened(bound, p.scale);
  const float inverse[3] = {1.0f / p.d[0], 1.0f / p.d[1], 1.0f / p.d[2]};
  RegionKey then{std::numeric_limits<float>::infinity(), -1};
  for (std::size_t q = 0; q < regions.size(); ++q) {
    const RegionBox& box = regions[q];
    if (box.empty) continue;
    float enter = ray.tmin, leave = t1;
    for (int k = 0; k < 3; ++k) {
      if (p.d[k] == 0) {  // (lo - o) / 0 would be NaN for an origin on a face
        if (p.o[k] < box.lo[k] || p.o[k] > box.hi[k])
          leave = -std::numeric_limits<float>::infinity();
        continue;
      }
      float near = (box.lo[k] - p.o[k]) * inverse[k];
      float far = (box.hi[k] - p.o[k]) * inverse[k];
      if (near > far) std::swap(near, far);
      enter = std::max(enter, near);
      leave = std::min(leave, far);
    }
    if (!(enter <= leave)) continue;
    const RegionKey key{enter, static_cast<int>(q)};
    if (!(after < key)) continue;
    if (key < steps.next) {
      then = steps.next;
      steps.next = key;
    } else if (key < then) {
      then = key;
    }
  }
  steps.then = then.entry;
  return steps;
}

RegionKey next_region(std::span<const RegionBox> regions, const Ray& ray, float bound,
                      RegionKey after) {
  return next_regions(regions, ray, bound, after).next;
}

float reach(const Ray& ray, float bound) {
  const RayParts p = parts_of(ray);
  return p.valid ? widened(bound, p.scale) : std::numeric_limits<float>::quiet_NaN();
}

}  // namespace sphray::mpi
