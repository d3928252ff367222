#include "sphray/mpi/regions.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace sphray::mpi {

RegionBox region_box(SphereView spheres) {
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::numeric_limits<double>::infinity();
    hi[k] = -std::numeric_limits<double>::infinity();
  }
  bool empty = true;
  for (std::size_t i = 0; i < spheres.count; ++i) {
    const double c[3] = {spheres.cx[i], spheres.cy[i], spheres.cz[i]};
    const double r = spheres.radius[i];
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

RegionKey next_region(std::span<const RegionBox> regions, const Ray& ray, float bound,
                      RegionKey after) {
  const float o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
  const float d[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
  RegionKey next{std::numeric_limits<float>::infinity(), -1};
  bool valid = !std::isnan(ray.tmin) && !std::isnan(bound) && (d[0] != 0 || d[1] != 0 || d[2] != 0);
  float reach = 0, speed = 0;  // the largest |o| and |d| components
  for (int k = 0; k < 3; ++k) {
    valid = valid && std::isfinite(o[k]) && std::isfinite(d[k]);
    reach = std::max(reach, std::abs(o[k]));
    speed = std::max(speed, std::abs(d[k]));
  }
  if (!valid) return next;
  // The kernel rounds t relative to the origin's and the sphere's size (the latter is in the
  // box's padding): the bound is widened by the same relative slack, which also covers the
  // rounding of the slab test below.
  const float t1 = bound + kRegionSlack * (std::abs(bound) + reach / speed);
  const float inverse[3] = {1.0f / d[0], 1.0f / d[1], 1.0f / d[2]};
  for (std::size_t q = 0; q < regions.size(); ++q) {
    const RegionBox& box = regions[q];
    if (box.empty) continue;
    float enter = ray.tmin, leave = t1;
    for (int k = 0; k < 3; ++k) {
      if (d[k] == 0) {  // (lo - o) / 0 would be NaN for an origin on a face
        if (o[k] < box.lo[k] || o[k] > box.hi[k]) leave = -std::numeric_limits<float>::infinity();
        continue;
      }
      float near = (box.lo[k] - o[k]) * inverse[k];
      float far = (box.hi[k] - o[k]) * inverse[k];
      if (near > far) std::swap(near, far);
      enter = std::max(enter, near);
      leave = std::min(leave, far);
    }
    if (!(enter <= leave)) continue;
    const RegionKey key{enter, static_cast<int>(q)};
    if (after < key && key < next) next = key;
  }
  return next;
}

Ray bounded_by(const Ray& ray, const Hit& best) {
  Ray bounded = ray;
  if (best.found()) bounded.tmax = std::nextafter(best.t, std::numeric_limits<float>::infinity());
  return bounded;
}

void keep_nearer(Hit& best, const Hit& hit) {
  if (hit.t < best.t || (hit.t == best.t && hit.id < best.id)) best = hit;
}

}  // namespace sphray::mpi
