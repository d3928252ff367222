// The pairs of a tree's spheres that overlap, written once over an xsimd architecture A: each
// leaf's box is walked down the tree, and every leaf from it on in slot order whose box meets it
// is tested against it sphere by sphere, a leaf of theirs in the lanes. Every pair is found once,
// by the earlier of its two leaves, with the operations overlapping() uses (point_lanes.hpp): the
// lower id's sphere is the query ball, the higher id's the sphere, so that a pair is listed
// exactly when overlapping(tree, c_i, r_i) lists j.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <xsimd/xsimd.hpp>

#include "brute/sphere_lanes.hpp"
#include "bvh/bvh_data.hpp"
#include "bvh/node.hpp"
#include "point/point_lanes.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"
#include "sphray/point_queries.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct OverlapPairs {
  using Lanes = PointLanes<A>;
  using Floats = typename Lanes::Floats;
  using Mask = typename Lanes::Mask;
  using Spheres = typename Lanes::Spheres;
  using Sphere = SphereLanes<A>;
  using Node = NodeView<const float>;
  static constexpr std::size_t kWidth = Lanes::kWidth;
  // The walk pushes every child that meets the box and pops one: at most kWidth a level.
  static constexpr std::size_t kStackSize = kBvhMaxDepth * kWidth;

  // How far two boxes may be apart and still hold spheres the test calls overlapping, relative
  // to the largest coordinate M of the tree's box: the computed |c_i - c_j| - r_j errs by a few
  // units in the last place of |c_i| + |c_j| + r_j <= 3 M (about 2^-21 M), and a leaf's own box
  // (c -+ r in float) by half a unit of M. 2^-16 M is far above both and costs no culling.
  static constexpr float kMargin = 0x1p-16f;

  // One leaf's spheres, lane by lane, and the box of its valid ones widened by the margin.
  struct Leaf {
    std::size_t first;
    unsigned valid;
    alignas(64) float x[kWidth], y[kWidth], z[kWidth], r[kWidth];
    float lo[3], hi[3];
  };

  // Part `part` of `parts`: the pairs found by that share of the leaves, appended to out.
  static void find(const BvhData& bvh, std::size_t part, std::size_t parts,
                   std::vector<IdPair>& out) {
    const std::size_t leaves = bvh.spheres.count / kWidth;
    if (bvh.node_count == 0 || leaves == 0) return;
    const float margin = kMargin * largest_coordinate(bvh);
    for (std::size_t k = leaves * part / parts; k < leaves * (part + 1) / parts; ++k) {
      Leaf leaf;
      if (!load(bvh, k * kWidth, margin, leaf)) continue;
      if (bvh.count <= kWidth)  // one leaf at slot 0, no node to walk (distance_walk.hpp)
        test(bvh, leaf, leaf.first, out);
      else
        walk(bvh, leaf, out);
    }
  }

 private:
  // The largest |coordinate| of the boxes under the root.
  static float largest_coordinate(const BvhData& bvh) {
    if (bvh.count <= kWidth) return 0.0f;  // no walk, no margin
    const Node root(bvh.nodes, 0, kWidth);
    float m = 0.0f;
    for (std::size_t k = 0; k < kWidth; ++k)
      if (!root.ref(k).is_empty())
        for (int axis = 0; axis < 3; ++axis)
          m = std::max({m, std::fabs(root.lo(axis, k)), std::fabs(root.hi(axis, k))});
    return m;
  }

  // Whether the leaf at slot `first` holds a valid sphere; if so, leaf is filled in.
  static bool load(const BvhData& bvh, std::size_t first, float margin, Leaf& leaf) {
    const Spheres sp = Sphere::load(bvh.spheres, first);
    leaf.first = first;
    leaf.valid = LaneReduce<A>::bits(Lanes::valid(sp));
    if (leaf.valid == 0) return false;
    sp.cx.store_aligned(leaf.x);
    sp.cy.store_aligned(leaf.y);
    sp.cz.store_aligned(leaf.z);
    sp.r.store_aligned(leaf.r);
    const float* c[3] = {leaf.x, leaf.y, leaf.z};
    for (int axis = 0; axis < 3; ++axis) {
      leaf.lo[axis] = INFINITY;
      leaf.hi[axis] = -INFINITY;
      for (unsigned bits = leaf.valid; bits != 0; bits &= bits - 1) {
        const auto a = static_cast<unsigned>(__builtin_ctz(bits));
        leaf.lo[axis] = std::min(leaf.lo[axis], c[axis][a] - leaf.r[a]);
        leaf.hi[axis] = std::max(leaf.hi[axis], c[axis][a] + leaf.r[a]);
      }
      leaf.lo[axis] -= margin;
      leaf.hi[axis] += margin;
    }
    return true;
  }

  // The leaves from this one on in slot order whose boxes meet its box.
  static void walk(const BvhData& bvh, const Leaf& leaf, std::vector<IdPair>& out) {
    Floats lo[3], hi[3];
    for (int axis = 0; axis < 3; ++axis) {
      lo[axis] = Floats(leaf.lo[axis]);
      hi[axis] = Floats(leaf.hi[axis]);
    }
    ChildRef stack[kStackSize];
    std::size_t top = 0;
    stack[top++] = ChildRef::node(0);
    while (top != 0) {
      const ChildRef ref = stack[--top];
      if (ref.is_leaf()) {
        if (ref.first(kWidth) >= leaf.first) test(bvh, leaf, ref.first(kWidth), out);
        continue;
      }
      const Node node(bvh.nodes, ref.node_index(), kWidth);
      Mask meets(true);
      for (std::size_t axis = 0; axis < 3; ++axis) {
        const Floats node_lo = Floats::load_aligned(node.plane_row(2 * axis));
        const Floats node_hi = Floats::load_aligned(node.plane_row(2 * axis + 1));
        meets = meets & (node_lo <= hi[axis]) & (node_hi >= lo[axis]);
      }
      // An empty child's box (+inf, -inf) meets nothing unless the margin is infinite, which
      // only a tree reaching float's range gives: its reference is checked too.
      for (unsigned bits = LaneReduce<A>::bits(meets); bits != 0; bits &= bits - 1) {
        const ChildRef child = node.ref(static_cast<unsigned>(__builtin_ctz(bits)));
        if (!child.is_empty()) stack[top++] = child;
      }
    }
  }

  // The overlapping pairs of leaf's spheres with those of the leaf at slot `first` (with the
  // later lanes only, when that is leaf itself).
  static void test(const BvhData& bvh, const Leaf& leaf, std::size_t first,
                   std::vector<IdPair>& out) {
    const Spheres theirs = Sphere::load(bvh.spheres, first);
    const Mask valid = Lanes::valid(theirs);
    const std::uint32_t* ids = bvh.ids;
    for (unsigned mine = leaf.valid; mine != 0; mine &= mine - 1) {
      const auto a = static_cast<unsigned>(__builtin_ctz(mine));
      const Floats d =
          Lanes::distance({Floats(leaf.x[a]), Floats(leaf.y[a]), Floats(leaf.z[a])}, theirs);
      const Floats ra(leaf.r[a]);
      // Ball a around sphere b (a the lower id), and ball b around sphere a (b the lower).
      const unsigned a_asks = LaneReduce<A>::bits(valid & (d - theirs.r < ra));
      const unsigned b_asks = LaneReduce<A>::bits(valid & (d - ra < theirs.r));
      unsigned candidates = a_asks | b_asks;
      if (first == leaf.first) candidates &= ~((2u << a) - 1u);  // each pair of a leaf once
      const std::uint32_t id_a = ids[leaf.first + a];
      for (; candidates != 0; candidates &= candidates - 1) {
        const auto b = static_cast<unsigned>(__builtin_ctz(candidates));
        const std::uint32_t id_b = ids[first + b];
        if (((id_a < id_b ? a_asks : b_asks) >> b & 1u) != 0)
          out.push_back({std::min(id_a, id_b), std::max(id_a, id_b)});
      }
    }
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
