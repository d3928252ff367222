// How far a point may be from the spheres under a node's children, written once over an xsimd
// architecture A and the point's scalar S: per child, a lower bound on the signed distance that
// point/point_lanes.hpp computes for any sphere in its box, so that the walk by distance
// (distance_walk.hpp) can skip the box and still return what brute force returns, bit for bit.
#pragma once

#include <cstddef>
#include <limits>

#include <xsimd/xsimd.hpp>

#include "bvh/box_test.hpp"
#include "bvh/node.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct BoxDistance {
  using Box = BoxTest<A, S>;
  using Floats = typename Box::Floats;
  using Node = typename Box::Node;
  using Near = typename Box::Near;
  static constexpr std::size_t kPieces = Box::kPieces;

  // A relative margin far above the rounding of either side: the kernel's distance to a sphere
  // in the box errs by a few units in the last place of |p - c| + r, at most the distance to
  // the box's far corner F, and so does this bound's own arithmetic. Float's margin serves
  // double too: double's rounding is smaller still, and the boxes are float's either way.
  static constexpr S kMargin = S(0x1p-18);

  // For a point outside a box, every sphere in it (its box holds the exact sphere: the builder
  // widens it, bvh/prim.hpp) is at least as far as the box: D - kMargin F bounds the computed
  // distances from below. For a point inside a box, nothing bounds them but -radius: -inf.
  // An empty child (lo = +inf, hi = -inf) gives NaN, which no comparison passes.
  // Per child, in kPieces batches of S (a double tree's float planes, widened).
  static Near lower_bound(const Node& node, const Floats& px, const Floats& py, const Floats& pz) {
    Near lower;
    for (std::size_t p = 0; p < kPieces; ++p) {
      Floats outside2(S(0)), far(S(0));
      axis(node, 0, p, px, outside2, far);
      axis(node, 1, p, py, outside2, far);
      axis(node, 2, p, pz, outside2, far);
      const Floats distance = xsimd::sqrt(outside2);
      lower.piece[p] = xsimd::select(outside2 > Floats(S(0)), distance - Floats(kMargin) * far,
                                     Floats(-std::numeric_limits<S>::infinity()));
    }
    return lower;
  }

  // The children whose lower bound is at most bound, as bits.
  static unsigned within(const Near& lower, S bound) {
    unsigned bits = 0;
    for (std::size_t p = 0; p < kPieces; ++p)
      bits |= LaneReduce<A>::bits(lower.piece[p] <= Floats(bound)) << (p * Box::kLanes);
    return bits;
  }

 private:
  static void axis(const Node& node, std::size_t a, std::size_t piece, const Floats& p,
                   Floats& outside2, Floats& far) {
    const Floats lo = Box::plane(node, 2 * a, piece);
    const Floats hi = Box::plane(node, 2 * a + 1, piece);
    const Floats below = lo - p, above = p - hi;
    const Floats out = xsimd::max(xsimd::max(below, above), Floats(S(0)));
    outside2 = outside2 + out * out;
    far = far + xsimd::max(xsimd::abs(below), xsimd::abs(above));
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
