// The tree walked by distance from a point, written once over an xsimd architecture A and the
// point's scalar S: the leaves whose boxes may hold a sphere within bound() of the point,
// nearest child first, each child's lower bound from box_distance.hpp. The point queries
// (point/point_queries.hpp) are its callers; the ray walk (walk.hpp) orders children along a
// ray instead.
#pragma once

#include <cstddef>

#include <xsimd/xsimd.hpp>

#include "bvh/box_distance.hpp"
#include "bvh/box_test.hpp"
#include "bvh/bvh_data.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct DistanceWalk {
  using Box = BoxTest<A, S>;
  using Floats = typename Box::Floats;
  using Distance = BoxDistance<A, S>;
  // Children per node and slots per leaf: a float batch's lanes, whatever S (box_test.hpp).
  static constexpr std::size_t kWidth = Box::kWidth;

  // Visits the leaves whose children's lower bounds are at most bound(), nearest first, the
  // point given as one broadcast batch per coordinate; leaf(first slot) returns whether to
  // stop. bound() may shrink as leaves are visited (the nearest sphere's search), and entries
  // pushed earlier are then skipped when popped.
  template <class Bound, class Leaf>
  static void visit(const BasicBvhData<S>& bvh, const Floats& x, const Floats& y, const Floats& z,
                    Bound&& bound, Leaf&& leaf) {
    if (bvh.node_count == 0) return;
    if (bvh.count <= kWidth) {  // one leaf at slot 0, as the ray walk reads it
      leaf(0);
      return;
    }
    typename Box::StackEntry stack[Box::kStackSize];
    std::size_t top = 0;
    ChildRef ref = ChildRef::node(0);
    for (;;) {
      if (ref.is_leaf()) {
        if (leaf(ref.first(kWidth))) return;
      } else {
        const typename Box::Node node(bvh.nodes, ref.node_index(), kWidth);
        const typename Box::Near lower = Distance::lower_bound(node, x, y, z);
        const unsigned bits = Distance::within(lower, bound());
        if (bits != 0) {
          ref = Box::enter(node, bits, lower, stack, top);
          continue;
        }
      }
      do {
        if (top == 0) return;
        --top;
      } while (stack[top].tnear > bound());
      ref = stack[top].ref;
    }
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
