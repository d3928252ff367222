// How far a point may be from the spheres under a node's children, written once over an xsimd
// architecture A: per child, a lower bound on the signed distance that point/point_lanes.hpp
// computes for any sphere in its box, so that the walk by distance (distance_walk.hpp) can skip
// the box and still return what brute force returns, bit for bit.
#pragma once

#include <cstddef>

#include <xsimd/xsimd.hpp>

#include "bvh/node.hpp"
#include "simd/isa_namespace.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct BoxDistance {
  using Floats = xsimd::batch<float, A>;
  using Node = NodeView<const float>;

  // A relative margin far above the rounding of either side: the kernel's distance to a sphere
  // in the box errs by a few units in the last place of |p - c| + r, at most the distance to
  // the box's far corner F, and so does this bound's own arithmetic.
  static constexpr float kMargin = 0x1p-18f;

  // For a point outside a box, every sphere in it (its box holds the exact sphere: the builder
  // widens it, bvh/prim.hpp) is at least as far as the box: D - kMargin F bounds the computed
  // distances from below. For a point inside a box, nothing bounds them but -radius: -inf.
  // An empty child (lo = +inf, hi = -inf) gives NaN, which no comparison passes.
  static Floats lower_bound(const Node& node, const Floats& px, const Floats& py,
                            const Floats& pz) {
    Floats outside2(0.0f), far(0.0f);
    axis(node, 0, px, outside2, far);
    axis(node, 1, py, outside2, far);
    axis(node, 2, pz, outside2, far);
    const Floats distance = xsimd::sqrt(outside2);
    return xsimd::select(outside2 > Floats(0.0f), distance - Floats(kMargin) * far,
                         Floats(-__builtin_inff()));
  }

 private:
  static void axis(const Node& node, int a, const Floats& p, Floats& outside2, Floats& far) {
    const Floats lo = Floats::load_aligned(node.plane_row(2 * static_cast<std::size_t>(a)));
    const Floats hi = Floats::load_aligned(node.plane_row(2 * static_cast<std::size_t>(a) + 1));
    const Floats below = lo - p, above = p - hi;
    const Floats out = xsimd::max(xsimd::max(below, above), Floats(0.0f));
    outside2 = outside2 + out * out;
    far = far + xsimd::max(xsimd::abs(below), xsimd::abs(above));
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
