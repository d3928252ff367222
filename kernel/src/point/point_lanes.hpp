// A point against the spheres in the lanes of one SIMD register, written once over an xsimd
// architecture A: the signed distance from the point to each sphere's surface, |p - c| - r,
// negative inside. The same operations in the same order on every instruction set and in the
// scalar reference (point_reference.cpp), without fused multiply-adds: every kernel returns
// the same bits.
#pragma once

#include <cstddef>

#include <xsimd/xsimd.hpp>

#include "brute/radius_range.hpp"
#include "brute/sphere_lanes.hpp"
#include "simd/isa_namespace.hpp"
#include "sphray/vec3.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct PointLanes {
  using Floats = xsimd::batch<float, A>;
  using Mask = xsimd::batch_bool<float, A>;
  using Spheres = typename SphereLanes<A>::Spheres;
  static constexpr std::size_t kWidth = Floats::size;

  struct Point {
    Floats x, y, z;
  };

  static Point setup(Vec3 p) { return {Floats(p.x), Floats(p.y), Floats(p.z)}; }

  // Per lane: the signed distance, and whether the sphere takes part at all (the contract's
  // valid spheres: a finite centre, kMinRadius <= r < kRadiusLimit, which also refuses a NaN
  // radius; x - x is 0 exactly for finite x, NaN otherwise). Padding lanes have radius 0.
  static Floats signed_distance(const Point& p, const Spheres& sp, Mask& valid) {
    const Floats gx = sp.cx - p.x, gy = sp.cy - p.y, gz = sp.cz - p.z;
    const Floats zero(0.0f);
    valid = (sp.r >= Floats(kMinRadius)) & (sp.r < Floats(kRadiusLimit)) &
            (((sp.cx - sp.cx) + (sp.cy - sp.cy)) + (sp.cz - sp.cz) == zero);
    return xsimd::sqrt(gx * gx + (gy * gy + gz * gz)) - sp.r;
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
