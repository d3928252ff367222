// The leaf test of the SIMD walk, written once over an xsimd architecture A and the scalar S of
// the tree's spheres: a leaf is an aligned run of slots (its spheres, then never-hit padding),
// one batch of S or two, tested with the sphere kernel's roots and folded into the best hit in
// the contract's order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

#include <xsimd/xsimd.hpp>

#include "brute/ray_lanes.hpp"
#include "brute/sphere_lanes.hpp"
#include "bvh/bvh_data.hpp"
#include "bvh/robust_slab.hpp"
#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct LeafTest {
  using Batch = SphereLanes<A, S>;
  using Data = BasicBvhData<S>;
  using Floats = typename Batch::Floats;
  using Mask = typename Batch::Mask;
  using Uints = typename Batch::Uints;
  // A leaf holds as many slots as a float batch has lanes, whatever S (box_test.hpp): kPieces
  // batches of S.
  static constexpr std::size_t kLanes = Batch::kWidth;
  static constexpr std::size_t kWidth = xsimd::batch<float, A>::size;
  static constexpr std::size_t kPieces = kWidth / kLanes;

  // Folds the hits of the leaf at slot i into best, a batch at a time. Leaf order is not id
  // order, so a tie on t goes to the lower id explicitly. Two forms, the same result:
  // - kBranchFree = false: the sphere kernel's early exit when no lane's discriminant is
  //   non-negative, then a loop over the lanes that hit.
  // - kBranchFree = true: no branch on the lanes but "any hit at all": the roots of every lane,
  //   then the smallest t by a horizontal min and its id.
  // The branches win in sparse scenes, where a ray tests about one leaf and the predictor
  // learns its outcome. Scattered rays in a dense scene test several leaves, about half of
  // them with a lane whose discriminant is non-negative: there the branches are coin tosses,
  // each mispredicted one costing more than the arithmetic it skips, and coherent rays lose
  // nothing without them. The tree picks (QueryPlan::branch_free_leaves).
  // count: the leaf's spheres; the batches past them hold padding alone and are not read.
  template <bool kBranchFree, bool kMasked>
  SPHRAY_FORCE_INLINE static void keep_closest(const Data& bvh, const typename Batch::RaySetup& s,
                                               std::size_t i, BasicHit<S>& best,
                                               std::size_t count = kWidth) {
    for (std::size_t p = 0; p < batches(count); ++p)
      keep_closest_in_batch<kBranchFree, kMasked>(bvh, s, i + p * kLanes, best);
  }

  // The batches that hold a leaf's count spheres.
  SPHRAY_FORCE_INLINE static std::size_t batches(std::size_t count) {
    return kPieces == 1 ? 1 : (count + kLanes - 1) / kLanes;
  }

  template <bool kBranchFree, bool kMasked>
  SPHRAY_FORCE_INLINE static void keep_closest_in_batch(const Data& bvh,
                                                        const typename Batch::RaySetup& s,
                                                        std::size_t i, BasicHit<S>& best) {
    Floats t;
    Mask live;
    constexpr Skip kSkip = kBranchFree ? Skip::kNever : Skip::kAfterDisc;
    const auto spheres = Batch::template load_seen<kMasked>(bvh.spheres, i, s);
    if (!Batch::template roots<kSkip>(s, spheres, t, live)) return;
    const Mask hit = live & (t > s.tmin) & (t <= Floats(best.t));
    if constexpr (kBranchFree) {
      if (xsimd::none(hit)) return;
      const Floats m = LaneReduce<A>::template all_min<S>(
          xsimd::select(hit, t, Floats(std::numeric_limits<S>::infinity())));
      keep_closer(best, m.get(0), lowest_id(bvh, i, LaneReduce<A>::bits(hit & (t == m))));
    } else {
      unsigned bits = LaneReduce<A>::bits(hit);
      if (bits == 0) return;
      alignas(64) S lanes[kLanes];
      t.store_aligned(lanes);
      for (; bits != 0; bits &= bits - 1) {
        const auto lane = static_cast<unsigned>(__builtin_ctz(bits));
        keep_closer(best, lanes[lane], bvh.ids[i + lane]);
      }
    }
  }

  // Whether some sphere of the leaf at slot i lies on the ray strictly between tmin and tmax:
  // the occlusion test, the same for a single ray and a packet's rays.
  template <bool kMasked>
  SPHRAY_FORCE_INLINE static bool any_hit(const Data& bvh, const typename Batch::RaySetup& s,
                                          std::size_t i, std::size_t count = kWidth) {
    for (std::size_t p = 0; p < batches(count); ++p) {
      Floats t;
      Mask live;
      const auto spheres = Batch::template load_seen<kMasked>(bvh.spheres, i + p * kLanes, s);
      if (Batch::template roots<Skip::kAfterDisc>(s, spheres, t, live) &&
          xsimd::any(live & (t > s.tmin) & (t < Floats(s.tmax))))
        return true;
    }
    return false;
  }

  // any_hit transposed, for a packet's rays at one leaf: rays in the lanes (rays holds their
  // setups lane by lane, tmax and ray_masks their ends and masks) against the leaf's spheres,
  // slots [i, i + count), one at a time (RayLanes::any_hit). Returns the lanes of open that
  // some sphere blocks strictly between their tmin and tmax; each lane's answer is any_hit's
  // for its ray, bit for bit. The padding slots after count, which no ray hits, are skipped.
  template <bool kMasked>
  SPHRAY_FORCE_INLINE static Mask any_hit_across(const Data& bvh,
                                                 const typename Batch::RaySetup& rays,
                                                 const Floats& tmax, const Uints& ray_masks,
                                                 std::size_t i, std::size_t count, Mask open) {
    return RayLanes<A>::template any_hit<kMasked>(bvh.spheres, rays, tmax, ray_masks, i, count,
                                                  open);
  }

  // The lowest id among the lanes of the leaf at slot i whose bits are set (at least one).
  // Several lanes share the smallest t only for equal spheres: the loop rarely runs.
  static std::uint32_t lowest_id(const Data& bvh, std::size_t i, unsigned lanes) {
    std::uint32_t id = bvh.ids[i + static_cast<unsigned>(__builtin_ctz(lanes))];
    for (lanes &= lanes - 1; lanes != 0; lanes &= lanes - 1) {
      const std::uint32_t other = bvh.ids[i + static_cast<unsigned>(__builtin_ctz(lanes))];
      id = other < id ? other : id;
    }
    return id;
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
