// The pairs of a tree's spheres that overlap, written once over an xsimd architecture A and the
// scalar S (a double tree's float node planes read widened, its leaves kPieces batches): each
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
#include <limits>
#include <vector>

#include <xsimd/xsimd.hpp>

#include "brute/sphere_lanes.hpp"
#include "bvh/box_test.hpp"
#include "bvh/bvh_data.hpp"
#include "bvh/node.hpp"
#include "point/id_collector.hpp"
#include "point/point_lanes.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"
#include "sphray/point_queries.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct OverlapPairs {
  using Lanes = PointLanes<A, S>;
  using Floats = typename Lanes::Floats;
  using Mask = typename Lanes::Mask;
  using Spheres = typename Lanes::Spheres;
  using Sphere = SphereLanes<A, S>;
  using Box = BoxTest<A, S>;
  using Node = typename Box::Node;
  using Data = BasicBvhData<S>;
  // A leaf holds kWidth slots (a float batch's lanes, whatever S), kPieces batches of S.
  static constexpr std::size_t kLanes = Lanes::kWidth;
  static constexpr std::size_t kWidth = Box::kWidth;
  static constexpr std::size_t kPieces = Box::kPieces;
  // The walk pushes every child that meets the box and pops one: at most kWidth a level.
  static constexpr std::size_t kStackSize = kBvhMaxDepth * kWidth;

  // How far two boxes may be apart and still hold spheres the test calls overlapping, relative
  // to the largest coordinate M of the tree's box: the computed |c_i - c_j| - r_j errs by a few
  // units in the last place of |c_i| + |c_j| + r_j <= 3 M (about 2^-21 M in float), and a
  // leaf's own box (c -+ r) by half a unit of M. 2^-16 M is far above both and costs no
  // culling; in double, whose rounding is smaller still, it serves as well.
  static constexpr S kMargin = S(0x1p-16);

  // One leaf's spheres, lane by lane, and the box of its valid ones widened by the margin.
  struct Leaf {
    std::size_t first;
    unsigned valid;
    alignas(64) S x[kWidth], y[kWidth], z[kWidth], r[kWidth];
    S lo[3], hi[3];
  };

  // Part `part` of `parts`: the pairs found by that share of the leaves, appended to out.
  static void find(const Data& bvh, std::size_t part, std::size_t parts, std::vector<IdPair>& out) {
    const std::size_t leaves = bvh.spheres.count / kWidth;
    if (bvh.node_count == 0 || leaves == 0) return;
    const S margin = kMargin * largest_coordinate(bvh);
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
  static S largest_coordinate(const Data& bvh) {
    if (bvh.count <= kWidth) return S(0);  // no walk, no margin
    const Node root(bvh.nodes, 0, kWidth);
    S m = S(0);
    for (std::size_t k = 0; k < kWidth; ++k)
      if (!root.ref(k).is_empty())
        for (int axis = 0; axis < 3; ++axis)
          m = std::max({m, S(std::fabs(root.lo(axis, k))), S(std::fabs(root.hi(axis, k)))});
    return m;
  }

  // The leaf's kPieces batches of spheres at slot first.
  static void load_pieces(const Data& bvh, std::size_t first, Spheres (&pieces)[kPieces]) {
    for (std::size_t p = 0; p < kPieces; ++p)
      pieces[p] = Sphere::load(bvh.spheres, first + p * kLanes);
  }

  // Per slot of a leaf, as bits: the lanes of each piece where lanes(piece, p) holds.
  template <class PieceMask>
  static unsigned slot_bits(PieceMask&& lanes) {
    unsigned bits = 0;
    for (std::size_t p = 0; p < kPieces; ++p)
      bits |= LaneReduce<A>::bits(lanes(p)) << (p * kLanes);
    return bits;
  }

  // Whether the leaf at slot `first` holds a valid sphere; if so, leaf is filled in.
  static bool load(const Data& bvh, std::size_t first, S margin, Leaf& leaf) {
    Spheres pieces[kPieces];
    load_pieces(bvh, first, pieces);
    leaf.first = first;
    leaf.valid = slot_bits([&](std::size_t p) { return Lanes::valid(pieces[p]); });
    if (leaf.valid == 0) return false;
    for (std::size_t p = 0; p < kPieces; ++p) {
      pieces[p].cx.store_aligned(leaf.x + p * kLanes);
      pieces[p].cy.store_aligned(leaf.y + p * kLanes);
      pieces[p].cz.store_aligned(leaf.z + p * kLanes);
      pieces[p].r.store_aligned(leaf.r + p * kLanes);
    }
    const S* c[3] = {leaf.x, leaf.y, leaf.z};
    for (int axis = 0; axis < 3; ++axis) {
      leaf.lo[axis] = std::numeric_limits<S>::infinity();
      leaf.hi[axis] = -std::numeric_limits<S>::infinity();
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
  static void walk(const Data& bvh, const Leaf& leaf, std::vector<IdPair>& out) {
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
      const unsigned meets = slot_bits([&](std::size_t p) {
        Mask m(true);
        for (std::size_t axis = 0; axis < 3; ++axis) {
          const Floats node_lo = Box::plane(node, 2 * axis, p);
          const Floats node_hi = Box::plane(node, 2 * axis + 1, p);
          m = m & (node_lo <= hi[axis]) & (node_hi >= lo[axis]);
        }
        return m;
      });
      // An empty child's box (+inf, -inf) meets nothing unless the margin is infinite, which
      // only a tree reaching float's range gives: its reference is checked too.
      for (unsigned bits = meets; bits != 0; bits &= bits - 1) {
        const ChildRef child = node.ref(static_cast<unsigned>(__builtin_ctz(bits)));
        if (!child.is_empty()) stack[top++] = child;
      }
    }
  }

  // The overlapping pairs of leaf's spheres with those of the leaf at slot `first` (with the
  // later lanes only, when that is leaf itself).
  static void test(const Data& bvh, const Leaf& leaf, std::size_t first, std::vector<IdPair>& out) {
    Spheres theirs[kPieces];
    load_pieces(bvh, first, theirs);
    Mask valid[kPieces];
    for (std::size_t p = 0; p < kPieces; ++p)
      valid[p] = Lanes::valid(theirs[p]);
    const std::uint32_t* ids = bvh.ids;
    for (unsigned mine = leaf.valid; mine != 0; mine &= mine - 1) {
      const auto a = static_cast<unsigned>(__builtin_ctz(mine));
      const typename Lanes::Point centre{Floats(leaf.x[a]), Floats(leaf.y[a]), Floats(leaf.z[a])};
      const Floats ra(leaf.r[a]);
      // Ball a around sphere b (a the lower id), and ball b around sphere a (b the lower).
      unsigned a_asks = 0, b_asks = 0;
      for (std::size_t p = 0; p < kPieces; ++p) {
        const Floats d = Lanes::distance(centre, theirs[p]);
        a_asks |= LaneReduce<A>::bits(valid[p] & (d - theirs[p].r < ra)) << (p * kLanes);
        b_asks |= LaneReduce<A>::bits(valid[p] & (d - ra < theirs[p].r)) << (p * kLanes);
      }
      unsigned candidates = a_asks | b_asks;
      if (first == leaf.first) candidates &= ~((2u << a) - 1u);  // each pair of a leaf once
      const std::uint32_t id_a = ids[leaf.first + a];
      for (; candidates != 0; candidates &= candidates - 1) {
        const auto b = static_cast<unsigned>(__builtin_ctz(candidates));
        const std::uint32_t id_b = ids[first + b];
        if (((id_a < id_b ? a_asks : b_asks) >> b & 1u) != 0)
          append_pair(out, std::min(id_a, id_b), std::max(id_a, id_b));
      }
    }
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
