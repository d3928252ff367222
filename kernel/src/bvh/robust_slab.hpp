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
// A double tree's walk computes the same distances in double from its float planes (exact in
// double), so the same argument holds with u = 2^-53.
template <class S>
struct SlabScale {
  static constexpr S kUnit = sizeof(S) == 4 ? S(0x1p-24) : S(0x1p-53);
  static constexpr S kGamma3 = S(3) * kUnit / (S(1) - S(3) * kUnit);
  static constexpr S kExit = S(1) + S(2) * kGamma3;
  static constexpr S kEntry = S(1) - S(2) * kGamma3;
};
inline constexpr float kExitScale = SlabScale<float>::kExit;
inline constexpr float kEntryScale = SlabScale<float>::kEntry;

// A leaf's hit (t, id) replaces best when it is nearer, or as near with a lower id: the
// contract's order. The interval is open: t == tmax is no hit, so a tie counts only against an
// earlier hit.
template <class S>
void keep_closer(BasicHit<S>& best, S t, std::uint32_t id) {
  if (t < best.t || (t == best.t && best.id != kNoHit && id < best.id)) best = {t, id};
}

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
