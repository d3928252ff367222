// A point against the spheres in the lanes of one SIMD register, written once over an xsimd
// architecture A and the scalar S: the signed distance from the point to each sphere's
// surface, |p - c| - r, negative inside. The same operations in the same order on every
// instruction set and in the scalar reference (point_reference.cpp), without fused
// multiply-adds: every kernel returns the same bits.
#pragma once

#include <cstddef>

#include <xsimd/xsimd.hpp>

#include "brute/radius_range.hpp"
#include "brute/sphere_lanes.hpp"
#include "simd/isa_namespace.hpp"
#include "sphray/vec3.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct PointLanes {
  using Floats = xsimd::batch<S, A>;
  using Mask = xsimd::batch_bool<S, A>;
  using Spheres = typename SphereLanes<A, S>::Spheres;
  static constexpr std::size_t kWidth = Floats::size;

  struct Point {
    Floats x, y, z;
  };

  static Point setup(BasicVec3<S> p) { return {Floats(p.x), Floats(p.y), Floats(p.z)}; }

  // Per lane: whether the sphere takes part at all (the contract's valid spheres: a finite
  // centre, RadiusRange<S>::kMin <= r < kLimit, which also refuses a NaN radius; x - x is 0
  // exactly for finite x, NaN otherwise). Padding lanes have radius 0.
  static Mask valid(const Spheres& sp) {
    const Floats zero(S(0));
    return (sp.r >= Floats(RadiusRange<S>::kMin)) & (sp.r < Floats(RadiusRange<S>::kLimit)) &
           (((sp.cx - sp.cx) + (sp.cy - sp.cy)) + (sp.cz - sp.cz) == zero);
  }

  // Per lane: |p - c|, from c - p. Swapping p and c gives the same bits (IEEE negation is
  // exact and the squares drop the sign), which the pair query relies on.
  static Floats distance(const Point& p, const Spheres& sp) {
    const Floats gx = sp.cx - p.x, gy = sp.cy - p.y, gz = sp.cz - p.z;
    return xsimd::sqrt(gx * gx + (gy * gy + gz * gz));
  }

  // Per lane: the signed distance |p - c| - r, and whether the sphere is valid.
  static Floats signed_distance(const Point& p, const Spheres& sp, Mask& valid_lanes) {
    valid_lanes = valid(sp);
    return distance(p, sp) - sp.r;
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
