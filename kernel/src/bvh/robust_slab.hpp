// What the SIMD and the scalar walks share beyond the layout: the widening that makes their box
// test conservative, and the order in which a leaf's hits replace the best one.
#pragma once

#include <cstdint>

#include "simd/isa_namespace.hpp"
#include "sphray/ray.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

// Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013: with every slab distance computed as
// (plane - origin) * (1 / dir) in float, scaling the exit distance by 1 + 2 gamma(3), where
// gamma(n) = n u / (1 - n u) and u = 2^-24, makes the box test conservative: a ray that meets
// the box in exact arithmetic is never rejected. The walks widen each end of the interval by
// 2 gamma(3) of its own magnitude (kExitScale for a far end >= 0, kEntryScale for a near end
// >= 0, the other way round below 0), which holds for rays whose tmin is negative too.
inline constexpr float kGamma3 = 3.0f * 0x1p-24f / (1.0f - 3.0f * 0x1p-24f);
inline constexpr float kExitScale = 1.0f + 2.0f * kGamma3;
inline constexpr float kEntryScale = 1.0f - 2.0f * kGamma3;

// A leaf's hit (t, id) replaces best when it is nearer, or as near with a lower id: the
// contract's order. The interval is open: t == tmax is no hit, so a tie counts only against an
// earlier hit.
inline void keep_closer(Hit& best, float t, std::uint32_t id) {
  if (t < best.t || (t == best.t && best.id != kNoHit && id < best.id)) best = {t, id};
}

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
