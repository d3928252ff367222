// The SIMD walk's box test, written once over an xsimd architecture A and the ray's scalar S:
// one ray against the kWidth children boxes of a node per step, and the order in which the
// entered children are visited. A double tree's nodes hold float planes, read widened (exactly)
// a batch of doubles at a time, so that the test runs in double. A NaN slab distance (0 * inf)
// leaves the interval as it was, through Ordered's NaN rule: the slab is treated as unbounded,
// which is conservative.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#include "bvh/bvh_data.hpp"
#include "bvh/node.hpp"
#include "bvh/robust_slab.hpp"
#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"
#include "simd/ordered.hpp"
#include "simd/widen.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct BoxTest {
  using Floats = xsimd::batch<S, A>;
  using Mask = xsimd::batch_bool<S, A>;
  using Order = Ordered<A, S>;
  // A node has as many children as a float batch has lanes, whatever S: a double tree's nodes
  // are those of a float tree (bvh_data.hpp), tested kPieces batches of doubles at a time, so
  // that a double tree is as shallow as a float one.
  static constexpr std::size_t kLanes = Floats::size;
  static constexpr std::size_t kWidth = xsimd::batch<float, A>::size;
  static constexpr std::size_t kPieces = kWidth / kLanes;
  using Node = NodeView<const float>;
  // A node visit leaves at most kWidth - 1 entries above its ancestors' (one child is visited
  // next), and writes at most one slot past them: kBvhMaxDepth levels fit in this.
  static constexpr std::size_t kStackSize = kBvhMaxDepth * (kWidth - 1) + 1;

  // Where the ray enters each child of a node: kPieces batches, children 0 to kLanes - 1 first.
  struct Near {
    Floats piece[kPieces];
  };

  // What one ray contributes to every node. near[axis] is the offset (in batches of a node's
  // box arrays) of the plane the ray meets first on that axis: lo for a positive direction, hi
  // for a negative one. An empty box (lo = +inf, hi = -inf) is then never entered.
  struct NodeSetup {
    Floats ox, oy, oz, inv_dx, inv_dy, inv_dz, tmin;
    std::size_t near_x, near_y, near_z;
  };

  struct StackEntry {
    ChildRef ref;
    S tnear;
  };

  SPHRAY_FORCE_INLINE static NodeSetup node_setup(const BasicRay<S>& ray) {
    const BasicVec3<S>& o = ray.origin;
    const BasicVec3<S>& d = ray.dir;
    // A zero component gives an infinite inverse; its slab then yields +-inf, or NaN where the
    // origin lies exactly on a plane, and the NaN is ignored below.
    return {Floats(o.x),
            Floats(o.y),
            Floats(o.z),
            Floats(S(1) / d.x),
            Floats(S(1) / d.y),
            Floats(S(1) / d.z),
            Floats(ray.tmin),
            __builtin_signbit(d.x) ? 1u : 0u,
            __builtin_signbit(d.y) ? 3u : 2u,
            __builtin_signbit(d.z) ? 5u : 4u};
  }

  // Piece p of a row of box planes; a double tree's float planes widened exactly.
  SPHRAY_FORCE_INLINE static Floats plane(const Node& node, std::size_t row, std::size_t p = 0) {
    if constexpr (std::is_same_v<S, float>)
      return Floats::load_aligned(node.plane_row(row));
    else
      return Widen<A>::load_widened(node.plane_row(row) + p * kLanes);
  }

  // The children whose boxes the ray enters before best_t, as bits, and where it enters them.
  // kAhead: the ray passed QueryPlan::ahead(); both forms return the same bits and tnear for
  // such a ray.
  template <bool kAhead>
  SPHRAY_FORCE_INLINE static unsigned enter_children(const NodeSetup& s, const Node& node,
                                                     const Floats& best_t, Near& tnear) {
    unsigned bits = 0;
    for (std::size_t p = 0; p < kPieces; ++p)
      bits |= LaneReduce<A>::bits(enter_piece<kAhead>(s, node, p, best_t, tnear.piece[p]))
              << (p * kLanes);
    return bits;
  }

  template <bool kAhead>
  SPHRAY_FORCE_INLINE static Mask enter_piece(const NodeSetup& s, const Node& node, std::size_t p,
                                              const Floats& best_t, Floats& tnear) {
    const Floats near_x = (plane(node, s.near_x, p) - s.ox) * s.inv_dx;
    const Floats near_y = (plane(node, s.near_y, p) - s.oy) * s.inv_dy;
    const Floats near_z = (plane(node, s.near_z, p) - s.oz) * s.inv_dz;
    const Floats far_x = (plane(node, s.near_x ^ 1u, p) - s.ox) * s.inv_dx;
    const Floats far_y = (plane(node, s.near_y ^ 1u, p) - s.oy) * s.inv_dy;
    const Floats far_z = (plane(node, s.near_z ^ 1u, p) - s.oz) * s.inv_dz;
    const Floats shrink(SlabScale<S>::kEntry), grow(SlabScale<S>::kExit);
    Floats tfar_widened;
    if constexpr (kAhead) {
      // No NaN: plain min/max, in a tree rather than a chain (the box test is on the path from
      // one node to the next). tnear >= tmin >= 0, so it shrinks; a negative tfar (a box behind
      // the origin, with an exact sign: rounding keeps it) is rejected scaled either way.
      tnear = xsimd::max(xsimd::max(near_x, near_y), xsimd::max(near_z, s.tmin)) * shrink;
      tfar_widened = xsimd::min(xsimd::min(far_x, far_y), far_z) * grow;
    } else {
      const Floats inf(std::numeric_limits<S>::infinity()), zero(S(0));
      tnear = Order::greater_or_second(
          near_x, Order::greater_or_second(near_y, Order::greater_or_second(near_z, s.tmin)));
      const Floats tfar = Order::less_or_second(
          far_x, Order::less_or_second(far_y, Order::less_or_second(far_z, inf)));
      // Ize's tnear <= tfar * (1 + 2 gamma(3)) is conservative only for tfar >= 0, but tmin
      // may be negative and boxes then lie behind the origin: widen each end by 2 gamma(3) of
      // its own magnitude instead, which holds for either sign (and keeps +-inf, never making
      // NaN).
      tnear = tnear * xsimd::select(tnear >= zero, shrink, grow);
      tfar_widened = tfar * xsimd::select(tfar >= zero, grow, shrink);
    }
    // The widened tnear is also what best_t is compared with, here and when the child is
    // popped. <= best_t, not <: a sphere at exactly best_t with a lower id still wins.
    return (tnear <= tfar_widened) & (tnear <= best_t);
  }

  // Pushes the entered children but the nearest, farthest first, and returns the nearest: it
  // is visited next, with no trip through the stack. One or two children, what most nodes give
  // an incoherent ray, take a path without data-dependent branches.
  SPHRAY_FORCE_INLINE static ChildRef enter(const Node& node, unsigned bits, const Near& tnear,
                                            StackEntry* stack, std::size_t& top) {
    alignas(64) S t[kWidth];
    for (std::size_t p = 0; p < kPieces; ++p)
      tnear.piece[p].store_aligned(t + p * kLanes);
    const unsigned rest = bits & (bits - 1);
    if ((rest & (rest - 1)) == 0) {
      const auto a = static_cast<unsigned>(__builtin_ctz(bits));
      const auto b = rest != 0 ? static_cast<unsigned>(__builtin_ctz(rest)) : a;
      const bool b_first = t[b] <= t[a];
      const unsigned nearer = b_first ? b : a, farther = b_first ? a : b;
      // Written even for one child: the slot above top is free (see kStackSize).
      stack[top] = {node.ref(farther), t[farther]};
      top += rest != 0;
      return node.ref(nearer);
    }
    // Three or more: each child goes straight to its slot in the sorted run, its rank being
    // how many entered children precede it (farther, or as near and in a lower lane). No
    // comparison branches, only the loop over the children.
    for (unsigned left = bits; left != 0; left &= left - 1) {
      const auto lane = static_cast<unsigned>(__builtin_ctz(left));
      const Floats tl(t[lane]);
      unsigned farther = 0, tied = 0;
      for (std::size_t p = 0; p < kPieces; ++p) {
        farther |= LaneReduce<A>::bits(tnear.piece[p] > tl) << (p * kLanes);
        tied |= LaneReduce<A>::bits(tnear.piece[p] == tl) << (p * kLanes);
      }
      farther &= bits;
      tied &= bits & ((1u << lane) - 1u);
      stack[top + static_cast<unsigned>(__builtin_popcount(farther)) +
            static_cast<unsigned>(__builtin_popcount(tied))] = {node.ref(lane), t[lane]};
    }
    top += static_cast<unsigned>(__builtin_popcount(bits));
    return stack[--top].ref;
  }

  // enter() for a walk that reaches every leaf within a bound that never shrinks, whatever the
  // order (a count of every crossing): the entered children in lane order, with no ranks to
  // compute. Only the refs are stacked: such a walk's pop() reads no tnear.
  SPHRAY_FORCE_INLINE static ChildRef enter_any(const Node& node, unsigned bits, StackEntry* stack,
                                                std::size_t& top) {
    const auto first = static_cast<unsigned>(__builtin_ctz(bits));
    for (unsigned left = bits & (bits - 1); left != 0; left &= left - 1)
      stack[top++].ref = node.ref(static_cast<unsigned>(__builtin_ctz(left)));
    return node.ref(first);
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
