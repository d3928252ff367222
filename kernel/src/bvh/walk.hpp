// One ray's way through the tree, written once over an xsimd architecture A and the ray's
// scalar S: a leaf at a time, so that the single-ray queries can walk one ray to its end and the
// stream several in turns.
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "bvh/box_test.hpp"
#include "bvh/bvh_data.hpp"
#include "bvh/node.hpp"
#include "dispatch/query_plan.hpp"
#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct TreeWalk {
  using Box = BoxTest<A, S>;
  using Data = BasicBvhData<S>;
  using Floats = typename Box::Floats;
  static constexpr std::size_t kWidth = Box::kWidth;
  using Node = typename Box::Node;
  using StackEntry = typename Box::StackEntry;
  using NodeSetup = typename Box::NodeSetup;

  // One ray's way through the tree, a leaf at a time: descend() goes from the current entry
  // down the nearest entered children to a leaf (any entered child, without kOrdered), or finds
  // none; pop() takes the next entry off the stack, skipping those behind best_t. The
  // single-ray queries walk one ray to its end; the stream can walk several in turns.
  template <bool kAhead, bool kOrdered = true>
  struct Walk {
    NodeSetup s;
    std::size_t top;
    ChildRef ref;
    StackEntry stack[Box::kStackSize];

    SPHRAY_FORCE_INLINE void start(const BasicRay<S>& ray) {
      s = Box::node_setup(ray);
      top = 0;
      ref = ChildRef::node(0);  // the root
    }

    SPHRAY_FORCE_INLINE bool descend(const Data& bvh, S best_t, std::size_t& first) {
      while (!ref.is_leaf()) {
        const Node node(bvh.nodes, ref.node_index(), kWidth);
        typename Box::Near tnear;
        const unsigned bits = Box::template enter_children<kAhead>(s, node, Floats(best_t), tnear);
        if (bits == 0) return false;
        if constexpr (kOrdered)
          ref = Box::enter(node, bits, tnear, stack, top);
        else
          ref = Box::enter_any(node, bits, stack, top);
      }
      first = ref.first(kWidth);
      return true;
    }

    SPHRAY_FORCE_INLINE bool pop(S best_t) {
      if constexpr (!kOrdered) {  // a bound that never shrinks: every entry is within it
        if (top == 0) return false;
        ref = stack[--top].ref;
        return true;
      }
      // Entries behind the best hit so far can only hold farther spheres.
      do {
        if (top == 0) return false;
        --top;
      } while (stack[top].tnear > best_t);
      ref = stack[top].ref;
      return true;
    }

    // The first leaf after start(), if any.
    SPHRAY_FORCE_INLINE bool first_leaf(const Data& bvh, S best_t, std::size_t& first) {
      return descend(bvh, best_t, first) || next_leaf(bvh, best_t, first);
    }

    // The leaf after the one last returned, if any.
    SPHRAY_FORCE_INLINE bool next_leaf(const Data& bvh, S best_t, std::size_t& first) {
      while (pop(best_t))
        if (descend(bvh, best_t, first)) return true;
      return false;
    }
  };

  // Visits the tree: for each leaf the ray may reach before best_t, calls leaf(first slot,
  // sphere count), which returns whether to stop. Nodes are entered nearest child first; with
  // kOrdered false, in any order (for a walk that reaches every leaf within a bound that never
  // shrinks, where the order changes nothing but the cost of sorting the children).
  template <bool kOrdered = true, class Leaf>
  static void traverse(const Data& bvh, const BasicRay<S>& ray, const S& best_t, Leaf&& leaf) {
    if (bvh.node_count == 0) return;
    // A tree over at most kWidth spheres is one leaf, at slot 0: it is read directly, as brute
    // force reads a batch, without a test of the root's mostly empty child boxes.
    if (bvh.count <= kWidth) {
      leaf(0, bvh.count);
      return;
    }
    if (QueryPlan::ahead(ray))
      walk<true, kOrdered>(bvh, ray, best_t, leaf);
    else
      walk<false, kOrdered>(bvh, ray, best_t, leaf);
  }

  template <bool kAhead, bool kOrdered, class Leaf>
  static void walk(const Data& bvh, const BasicRay<S>& ray, const S& best_t, Leaf& leaf) {
    Walk<kAhead, kOrdered> w;
    w.start(ray);
    std::size_t first;
    for (bool more = w.first_leaf(bvh, best_t, first); more; more = w.next_leaf(bvh, best_t, first))
      if (leaf(first, w.ref.count(kWidth))) return;
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
