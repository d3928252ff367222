// The rays of sphray-mpi's benchmarks: a pinhole view of the particles' box from one side, the
// same on every rank (and in the routing simulation) from a ray's index alone.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "sphray/sphray.hpp"

namespace sphray::mpi::tools {

/// The box around the spheres that can be hit (centres padded by their radii).
inline std::pair<Vec3, Vec3> box_of(const SphereSoA& spheres) {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::uint32_t i = 0; i < spheres.size(); ++i) {
    const Vec3 c = spheres.center(i);
    const float r = spheres.radius(i);
    const float v[3] = {c.x, c.y, c.z};
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(v[k]) || !(r > 0) || !std::isfinite(r)) continue;
      lo[k] = std::min(lo[k], v[k] - r);
      hi[k] = std::max(hi[k], v[k] + r);
    }
  }
  return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
}

/// The axis a view looks along, by name: x, y or z (the default).
inline int axis_of(const std::string& name) {
  return name == "x" ? 0 : name == "y" ? 1 : 2;
}

// Ray i of a pinhole view of the box from in front along an axis (2: from +z, 0: from +x), on
// a square grid of side^2 rays: the same on every rank, from i alone. beside: the view is moved
// two box widths sideways, so that every ray passes the box (and each rank's tree rejects it at
// its root).
inline Ray view_ray(std::uint64_t i, std::uint64_t side, Vec3 lo, Vec3 hi, int axis, bool beside) {
  // The view from +z in a frame whose z is the axis, then back: swap axis and z.
  const auto swapped = [axis](Vec3 v) {
    float c[3] = {v.x, v.y, v.z};
    std::swap(c[axis], c[2]);
    return Vec3{c[0], c[1], c[2]};
  };
  lo = swapped(lo);
  hi = swapped(hi);
  const Vec3 center = 0.5f * (lo + hi);
  const float extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  const Vec3 eye{center.x, center.y, hi.z + extent};
  const float u = (static_cast<float>(i % side) + 0.5f) / static_cast<float>(side);
  const float v = (static_cast<float>(i / side) + 0.5f) / static_cast<float>(side);
  const float shift = beside ? 2.0f * extent : 0.0f;
  const Vec3 target{lo.x + shift + u * (hi.x - lo.x), lo.y + v * (hi.y - lo.y), hi.z};
  return Ray{swapped(eye), swapped(target - eye)};
}

}  // namespace sphray::mpi::tools
