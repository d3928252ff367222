// A packet of coherent rays through the tree at once, written once over an xsimd architecture A
// (Wald et al., "Ray tracing deformable scenes using dynamic bounding volume hierarchies", 2007:
// interval arithmetic over the packet; Overbeck et al., "Large ray packets for real-time
// Whitted ray tracing", 2008). The stream (bvh/stream.hpp) forms packets where the query plan
// says they win.
//
// Inner nodes: the packet's rays as one interval ray (their origins' and inverse directions'
// bounds), tested against the node's kWidth children in one batch, as one ray's box test: one
// node fetch and one test for up to kRays rays. Leaves: the leaf's box against the rays a batch
// at a time (one ray per lane), then the single-ray leaf test (bvh/leaf_test.hpp) for each ray
// that enters it, with that ray's own setup and best hit; for occlusion, where the plan says
// (QueryPlan::leaf_across), the same test transposed: the rays that enter in the lanes, the
// leaf's spheres one at a time.
//
// The result is each ray's intersect(bvh, ray), bit for bit: the leaf test is the single ray's,
// and every box test here is conservative (it rejects a box only when every ray's own test
// would), so each ray tests every leaf its own walk would reach with a best hit at least as
// near, and maybe more leaves, whose spheres the single walk had culled as farther: the closest
// hit, ties going to the lower id, does not depend on which extra spheres were tested.
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "brute/sphere_lanes.hpp"
#include "bvh/box_test.hpp"
#include "bvh/bvh_data.hpp"
#include "bvh/leaf_test.hpp"
#include "bvh/node.hpp"
#include "bvh/robust_slab.hpp"
#include "dispatch/query_plan.hpp"
#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct PacketWalk {
  using Batch = SphereLanes<A>;
  using Floats = typename Batch::Floats;
  using Mask = typename Batch::Mask;
  using Box = BoxTest<A>;
  using Node = typename Box::Node;
  using Leaves = LeafTest<A>;
  using Reduce = LaneReduce<A>;
  static constexpr std::size_t kWidth = Batch::kWidth;
  static constexpr std::size_t kRays = QueryPlan::kPacketRays;
  static_assert(kRays % kWidth == 0, "a packet is whole batches of rays");

  // The rays of a packet, one per lane (structure of arrays), and what the leaf test needs of
  // each. Every ray of a packet has passed SphereLanes::setup and QueryPlan::ahead, and all
  // share the signs of their direction components (one octant). Slots past count hold a
  // finite dummy ray whose best is -inf, which no box test enters.
  struct Rays {
    alignas(64) float ox[kRays], oy[kRays], oz[kRays];
    alignas(64) float inv_dx[kRays], inv_dy[kRays], inv_dz[kRays];
    alignas(64) float tmin[kRays];
    // The best hit so far (intersect) or the end of the ray (occluded: tmax while the ray is
    // free, -inf once it is blocked): a box entered beyond it is skipped.
    alignas(64) float best[kRays];
    std::uint32_t best_id[kRays];
    alignas(64) float dx[kRays], dy[kRays], dz[kRays], length[kRays], inv_a[kRays], tmax[kRays];
    alignas(64) std::uint32_t mask[kRays];
    std::size_t count;

    // The ray's SphereLanes::setup, rebuilt from what setup computed (same bits); ux, uy, uz
    // are read only by the brute-force pre-test, which leaves skip.
    SPHRAY_FORCE_INLINE typename Batch::RaySetup setup(std::size_t r) const {
      return {Floats(ox[r]),    Floats(oy[r]),   Floats(oz[r]), Floats(dx[r]), Floats(dy[r]),
              Floats(dz[r]),    Floats(0.0f),    Floats(0.0f),  Floats(0.0f),  Floats(length[r]),
              Floats(inv_a[r]), Floats(tmin[r]), tmax[r],       mask[r]};
    }

    // The setups of the rays of batch g (rays g * kWidth on), one per lane, for the leaf test
    // across rays (LeafTest::any_hit_across); tmax and mask are read as batches apart.
    SPHRAY_FORCE_INLINE typename Batch::RaySetup lanes(std::size_t g) const {
      const std::size_t r = g * kWidth;
      return {Floats::load_aligned(ox + r),
              Floats::load_aligned(oy + r),
              Floats::load_aligned(oz + r),
              Floats::load_aligned(dx + r),
              Floats::load_aligned(dy + r),
              Floats::load_aligned(dz + r),
              Floats(0.0f),
              Floats(0.0f),
              Floats(0.0f),
              Floats::load_aligned(length + r),
              Floats::load_aligned(inv_a + r),
              Floats::load_aligned(tmin + r),
              0.0f,
              0u};
    }
  };

  // Packs ray into slot count of p; s is its setup.
  SPHRAY_FORCE_INLINE static void add(Rays& p, const Ray& ray, const typename Batch::RaySetup& s,
                                      float best) {
    const std::size_t r = p.count++;
    p.ox[r] = ray.origin.x;
    p.oy[r] = ray.origin.y;
    p.oz[r] = ray.origin.z;
    // As BoxTest::node_setup computes them.
    p.inv_dx[r] = 1.0f / ray.dir.x;
    p.inv_dy[r] = 1.0f / ray.dir.y;
    p.inv_dz[r] = 1.0f / ray.dir.z;
    p.tmin[r] = ray.tmin;
    p.best[r] = best;
    p.best_id[r] = kNoHit;
    p.dx[r] = ray.dir.x;
    p.dy[r] = ray.dir.y;
    p.dz[r] = ray.dir.z;
    p.length[r] = s.length.get(0);
    p.inv_a[r] = s.inv_a.get(0);
    p.tmax[r] = ray.tmax;
    p.mask[r] = ray.mask;
  }

  // Fills the slots past count with rays no box test enters.
  static void pad(Rays& p) {
    for (std::size_t r = p.count; r < kRays; ++r) {
      p.ox[r] = p.oy[r] = p.oz[r] = 0.0f;
      p.inv_dx[r] = p.inv_dy[r] = p.inv_dz[r] = 1.0f;
      p.tmin[r] = 0.0f;
      p.best[r] = -__builtin_inff();
      // What the leaf test across rays computes in these lanes, and then ignores.
      p.dx[r] = p.dy[r] = p.dz[r] = 1.0f;
      p.length[r] = __builtin_sqrtf(3.0f);
      p.inv_a[r] = 1.0f / 3.0f;
      p.tmax[r] = 0.0f;
      p.mask[r] = 0u;
    }
  }

  // The packet as one ray of intervals, per axis: the origin bound that gives the smallest
  // entry distance (near_o) and the one that gives the largest exit (far_o), and the inverse
  // direction's bounds. Rounding is monotonic, so fl(fl(p - o) * inv) over the packet lies
  // between the values at the bounds' corners: the interval test below rejects a box only
  // when every ray's own test (BoxTest::enter_children) would.
  struct Interval {
    Floats near_o[3], far_o[3], inv_lo[3], inv_hi[3], tmin;
    std::size_t near_row[3];
  };

  static Interval interval(const Rays& p) {
    const float* o[3] = {p.ox, p.oy, p.oz};
    const float* inv[3] = {p.inv_dx, p.inv_dy, p.inv_dz};
    Interval iv;
    float tmin = p.tmin[0];
    for (std::size_t r = 1; r < p.count; ++r)
      tmin = p.tmin[r] < tmin ? p.tmin[r] : tmin;
    iv.tmin = Floats(tmin);
    for (int axis = 0; axis < 3; ++axis) {
      float o_lo = o[axis][0], o_hi = o_lo, i_lo = inv[axis][0], i_hi = i_lo;
      for (std::size_t r = 1; r < p.count; ++r) {
        o_lo = o[axis][r] < o_lo ? o[axis][r] : o_lo;
        o_hi = o[axis][r] > o_hi ? o[axis][r] : o_hi;
        i_lo = inv[axis][r] < i_lo ? inv[axis][r] : i_lo;
        i_hi = inv[axis][r] > i_hi ? inv[axis][r] : i_hi;
      }
      const bool negative = i_hi < 0.0f;  // one octant: every inverse has this sign
      iv.near_o[axis] = Floats(negative ? o_lo : o_hi);
      iv.far_o[axis] = Floats(negative ? o_hi : o_lo);
      iv.inv_lo[axis] = Floats(i_lo);
      iv.inv_hi[axis] = Floats(i_hi);
      iv.near_row[axis] = 2 * static_cast<std::size_t>(axis) + (negative ? 1u : 0u);
    }
    return iv;
  }

  // The children some ray of the packet may enter before max_best, and a lower bound of where
  // any does: BoxTest::enter_children's ahead form, over intervals.
  SPHRAY_FORCE_INLINE static Mask enter_children(const Interval& iv, const Node& node,
                                                 float max_best, Floats& tnear) {
    Floats near[3], far[3];
    for (int axis = 0; axis < 3; ++axis) {
      const Floats n = Box::plane(node, iv.near_row[axis]) - iv.near_o[axis];
      const Floats f = Box::plane(node, iv.near_row[axis] ^ 1u) - iv.far_o[axis];
      near[axis] = xsimd::min(n * iv.inv_lo[axis], n * iv.inv_hi[axis]);
      far[axis] = xsimd::max(f * iv.inv_lo[axis], f * iv.inv_hi[axis]);
    }
    tnear = xsimd::max(xsimd::max(near[0], near[1]), xsimd::max(near[2], iv.tmin)) *
            Floats(kEntryScale);
    const Floats tfar = xsimd::min(xsimd::min(far[0], far[1]), far[2]) * Floats(kExitScale);
    return (tnear <= tfar) & (tnear <= Floats(max_best));
  }

  // The rays of batch g (rays g * kWidth on) that enter the box of child lane of node, before
  // their own best: BoxTest::enter_children's ahead form with rays in the lanes, as bits.
  SPHRAY_FORCE_INLINE static unsigned enter_box(const Rays& p, const Interval& iv, const Node& node,
                                                std::size_t lane, std::size_t g) {
    return Reduce::bits(enter_box_lanes(p, iv, node, lane, g));
  }
  SPHRAY_FORCE_INLINE static Mask enter_box_lanes(const Rays& p, const Interval& iv,
                                                  const Node& node, std::size_t lane,
                                                  std::size_t g) {
    const std::size_t r = g * kWidth;
    const Floats ox = Floats::load_aligned(p.ox + r), oy = Floats::load_aligned(p.oy + r),
                 oz = Floats::load_aligned(p.oz + r);
    const Floats ix = Floats::load_aligned(p.inv_dx + r), iy = Floats::load_aligned(p.inv_dy + r),
                 iz = Floats::load_aligned(p.inv_dz + r);
    const auto plane = [&](std::size_t row) { return Floats(node.plane_row(row)[lane]); };
    const Floats near_x = (plane(iv.near_row[0]) - ox) * ix;
    const Floats near_y = (plane(iv.near_row[1]) - oy) * iy;
    const Floats near_z = (plane(iv.near_row[2]) - oz) * iz;
    const Floats far_x = (plane(iv.near_row[0] ^ 1u) - ox) * ix;
    const Floats far_y = (plane(iv.near_row[1] ^ 1u) - oy) * iy;
    const Floats far_z = (plane(iv.near_row[2] ^ 1u) - oz) * iz;
    const Floats tnear = xsimd::max(xsimd::max(near_x, near_y),
                                    xsimd::max(near_z, Floats::load_aligned(p.tmin + r))) *
                         Floats(kEntryScale);
    const Floats tfar = xsimd::min(xsimd::min(far_x, far_y), far_z) * Floats(kExitScale);
    return (tnear <= tfar) & (tnear <= Floats::load_aligned(p.best + r));
  }

  static float max_best(const Rays& p) {
    Floats m = Floats::load_aligned(p.best);
    for (std::size_t r = kWidth; r < kRays; r += kWidth)
      m = xsimd::max(m, Floats::load_aligned(p.best + r));
    return -Reduce::template all_min<float>(-m).get(0);  // no all_max: max x = -min(-x)
  }

  // A stack entry: the child, the packet's entry bound, and where its box is (node * kWidth +
  // lane), for the per-ray test of a leaf's box.
  struct Entry {
    ChildRef ref;
    float tnear;
    std::uint32_t box;
  };
  static constexpr std::size_t kStackSize = kBvhMaxDepth * kWidth + 1;

  // Visits the leaves the packet may reach, nearest first: leaf(node, lane) for the leaf in
  // child lane of node, which returns the packet's new max_best (-inf: every ray is done).
  // The tree has more than kWidth spheres (the root is a node).
  template <class Leaf>
  SPHRAY_FORCE_INLINE static void traverse(const BvhData& bvh, const Interval& iv, float best,
                                           Leaf&& leaf) {
    Entry stack[kStackSize];
    std::size_t top = 0;
    const bool beyond_caches = QueryPlan::beyond_caches(bvh);
    ChildRef ref = ChildRef::node(0);
    std::uint32_t box = 0;
    for (;;) {
      if (ref.is_leaf()) {
        const Node parent(bvh.nodes, box / kWidth, kWidth);
        best = leaf(parent, box % kWidth, ref.first(kWidth));
      } else {
        const Node node(bvh.nodes, ref.node_index(), kWidth);
        Floats tnear;
        const unsigned bits = Reduce::bits(enter_children(iv, node, best, tnear));
        push_sorted(node, ref.node_index(), bits, tnear, stack, top);
        if (beyond_caches) prefetch(bvh, node, bits);
      }
      // Entries beyond every ray's best hit so far can only hold farther spheres.
      do {
        if (top == 0) return;
        --top;
      } while (stack[top].tnear > best);
      ref = stack[top].ref;
      box = stack[top].box;
    }
  }

  // Asks the memory for what the entered children will read: a node's rows, a leaf's
  // spheres; the packet visits them in turn, and on a tree larger than the caches it would
  // otherwise wait on each.
  SPHRAY_FORCE_INLINE static void prefetch(const BvhData& bvh, const Node& node, unsigned bits) {
    for (unsigned left = bits; left != 0; left &= left - 1) {
      const ChildRef child = node.ref(static_cast<unsigned>(__builtin_ctz(left)));
      if (child.is_leaf()) {
        const std::size_t first = child.first(kWidth);
        __builtin_prefetch(bvh.spheres.cx + first);
        __builtin_prefetch(bvh.spheres.cy + first);
        __builtin_prefetch(bvh.spheres.cz + first);
        __builtin_prefetch(bvh.spheres.radius + first);
      } else {
        const float* rows = bvh.nodes + child.node_index() * kBvhNodeRows * kWidth;
        for (std::size_t row = 0; row < kBvhNodeRows; ++row)
          __builtin_prefetch(rows + row * kWidth);
      }
    }
  }

  // Pushes the entered children, farthest first (nearest on top), as BoxTest::enter does.
  SPHRAY_FORCE_INLINE static void push_sorted(const Node& node, std::size_t index, unsigned bits,
                                              const Floats& tnear, Entry* stack, std::size_t& top) {
    alignas(64) float t[kWidth];
    tnear.store_aligned(t);
    for (unsigned left = bits; left != 0; left &= left - 1) {
      const auto lane = static_cast<unsigned>(__builtin_ctz(left));
      const Floats tl(t[lane]);
      const unsigned farther = Reduce::bits(tnear > tl) & bits;
      const unsigned tied = Reduce::bits(tnear == tl) & bits & ((1u << lane) - 1u);
      stack[top + static_cast<unsigned>(__builtin_popcount(farther)) +
            static_cast<unsigned>(__builtin_popcount(tied))] = {
          node.ref(lane), t[lane], static_cast<std::uint32_t>(index * kWidth + lane)};
    }
    top += static_cast<unsigned>(__builtin_popcount(bits));
  }

  // The interval ray's own t: the rays start where they are, so the bound on best is theirs.
  // (bvh/line_packet.hpp slides the origins along the rays, and its frame shifts t.)
  struct OwnFrame {
    static float max_best(const Rays& p) { return PacketWalk::max_best(p); }
  };

  // Each ray's intersect(bvh, ray) into p.best, p.best_id.
  template <bool kBranchFree, bool kMasked>
  static void intersect(const BvhData& bvh, Rays& p) {
    intersect<kBranchFree, kMasked>(bvh, p, interval(p), OwnFrame{});
  }

  // The same through iv, an interval conservative for every ray of p, whose t is what frame
  // makes of the rays' best.
  template <bool kBranchFree, bool kMasked, class Frame>
  static void intersect(const BvhData& bvh, Rays& p, const Interval& iv, const Frame& frame) {
    traverse(
        bvh, iv, frame.max_best(p), [&](const Node& parent, std::size_t lane, std::size_t first) {
          for (std::size_t g = 0; g < kRays / kWidth; ++g) {
            for (unsigned bits = enter_box(p, iv, parent, lane, g); bits != 0; bits &= bits - 1) {
              const std::size_t r = g * kWidth + static_cast<unsigned>(__builtin_ctz(bits));
              Hit best{p.best[r], p.best_id[r]};
              Leaves::template keep_closest<kBranchFree, kMasked>(bvh, p.setup(r), first, best);
              p.best[r] = best.t;
              p.best_id[r] = best.id;
            }
          }
          return frame.max_best(p);
        });
  }

  // Each ray's occluded(bvh, ray): a blocked ray's best becomes -inf, which leaves it out of
  // every later box test.
  template <bool kMasked>
  static void occluded(const BvhData& bvh, Rays& p) {
    occluded<kMasked>(bvh, p, interval(p), OwnFrame{});
  }

  // The rays of batch g in enter against the leaf of count spheres at slot first, rays in the
  // lanes (LeafTest::any_hit_across): each blocked ray's best becomes -inf.
  template <bool kMasked>
  SPHRAY_FORCE_INLINE static void block_across(const BvhData& bvh, Rays& p, std::size_t g,
                                               std::size_t first, std::size_t count,
                                               const Mask& enter) {
    const std::size_t r = g * kWidth;
    const Mask blocked = Leaves::template any_hit_across<kMasked>(
        bvh, p.lanes(g), Floats::load_aligned(p.tmax + r), Batch::Uints::load_aligned(p.mask + r),
        first, count, enter);
    const Floats best = Floats::load_aligned(p.best + r);
    xsimd::select(blocked, Floats(-__builtin_inff()), best).store_aligned(p.best + r);
  }

  template <bool kMasked, class Frame>
  static void occluded(const BvhData& bvh, Rays& p, const Interval& iv, const Frame& frame) {
    traverse(
        bvh, iv, frame.max_best(p), [&](const Node& parent, std::size_t lane, std::size_t first) {
          const std::size_t spheres = parent.ref(lane).count(kWidth);
          for (std::size_t g = 0; g < kRays / kWidth; ++g) {
            const Mask enter = enter_box_lanes(p, iv, parent, lane, g);
            unsigned bits = Reduce::bits(enter);
            if (bits == 0) continue;
            if (QueryPlan::leaf_across(static_cast<unsigned>(__builtin_popcount(bits)), spheres)) {
              block_across<kMasked>(bvh, p, g, first, spheres, enter);
              continue;
            }
            for (; bits != 0; bits &= bits - 1) {
              const std::size_t r = g * kWidth + static_cast<unsigned>(__builtin_ctz(bits));
              if (Leaves::template any_hit<kMasked>(bvh, p.setup(r), first))
                p.best[r] = -__builtin_inff();
            }
          }
          return frame.max_best(p);
        });
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
