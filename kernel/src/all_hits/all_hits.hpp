// Every crossing of a ray with the spheres, written once over an xsimd architecture A and a
// scalar S: the roots of a batch of spheres at a time (brute/sphere_lanes.hpp), both of them
// kept where they lie in (tmin, tmax), over a view (brute force, float or double) or over the
// leaves of a tree the ray reaches (float; bvh/walk.hpp, with the search interval never
// shrinking: every hit is wanted).
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "all_hits/hit_list.hpp"
#include "brute/brute_force.hpp"
#include "brute/sphere_lanes.hpp"
#include "bvh/bvh_data.hpp"
#include "bvh/walk.hpp"
#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct AllHits {
  using Lanes = SphereLanes<A, S>;
  using Brute = BruteForce<A, S>;
  using List = BasicHitList<S>;
  using View = BasicSphereView<S>;
  using RayS = BasicRay<S>;
  using Tree = BasicBvhData<S>;
  using Walk = TreeWalk<A, S>;
  using Floats = typename Lanes::Floats;
  using Mask = typename Lanes::Mask;
  using RaySetup = typename Lanes::RaySetup;
  using Spheres = typename Lanes::Spheres;
  static constexpr std::size_t kWidth = Lanes::kWidth;

  static std::size_t intersect_all(View v, const RayS& ray, List& list) {
    return v.mask != nullptr ? intersect_all<true>(v, ray, list)
                             : intersect_all<false>(v, ray, list);
  }
  static std::size_t intersect_all(const Tree& bvh, const RayS& ray, List& list) {
    return bvh.spheres.mask != nullptr ? intersect_all<true>(bvh, ray, list)
                                       : intersect_all<false>(bvh, ray, list);
  }

  template <bool kMasked>
  static std::size_t intersect_all(View v, const RayS& ray, List& list) {
    RaySetup s;
    if (!Lanes::setup(ray, s)) return 0;
    v = Brute::clamp(v);
    const std::size_t whole = Brute::whole_batches(v);
    auto add = [&](const Spheres& sp, std::size_t first) SPHRAY_FORCE_INLINE_LAMBDA {
      add_batch<Skip::kPreTest>(
          s, sp, list, [&](unsigned lane) { return static_cast<std::uint32_t>(first + lane); });
    };
    for (std::size_t b = 0; b < whole; ++b)
      add(Lanes::template load_seen<kMasked>(v, b * kWidth, s), b * kWidth);
    if (whole * kWidth < v.count)
      add(Lanes::template load_tail_seen<kMasked>(v, whole * kWidth, s), whole * kWidth);
    return list.total();
  }

  template <bool kMasked>
  static std::size_t intersect_all(const Tree& bvh, const RayS& ray, List& list) {
    RaySetup s;
    if (!Lanes::setup(ray, s)) return 0;
    const S tmax = s.tmax;  // the walk's bound: it never shrinks
    auto add = [&](std::size_t first, std::size_t count)
                   SPHRAY_FORCE_INLINE_LAMBDA { add_leaf<kMasked>(bvh, s, first, count, list); };
    if (list.counts_only()) {
      // A count reaches every leaf in (tmin, tmax) whatever the order: no children to sort.
      Walk::template traverse<false>(
          bvh, ray, tmax, [&](std::size_t first, std::size_t count) SPHRAY_FORCE_INLINE_LAMBDA {
            add(first, count);
            return false;
          });
      return list.total();
    }
    // A list is kept nearest first: leaves in that order place most crossings of a long ray
    // behind the kept ones, counted lane-parallel (add_batch). In any order they were slower
    // (docs/history.md, "count_hits without sorting").
    Walk::traverse(bvh, ray, tmax,
                   [&](std::size_t first, std::size_t count) SPHRAY_FORCE_INLINE_LAMBDA {
                     // A leaf's ids lie apart from its spheres: asked for early, their cache line
                     // arrives while the roots are computed instead of stalling the first crossing
                     // placed.
                     __builtin_prefetch(bvh.ids + first);
                     add(first, count);
                     return false;
                   });
    return list.total();
  }

  // The nearest crossings alone (the list's capacity, at least 1): once the list is full, the
  // walk's bound is its last t, so that the leaves behind it are never read, as the closest hit
  // stops at the nearest found so far. A crossing at that t may still displace the last kept
  // one (a lower id), and the walk still enters boxes that begin at it. Returns how many it
  // kept.
  static std::size_t intersect_nearest(const Tree& bvh, const RayS& ray, List& list) {
    return bvh.spheres.mask != nullptr ? intersect_nearest<true>(bvh, ray, list)
                                       : intersect_nearest<false>(bvh, ray, list);
  }

  template <bool kMasked>
  static std::size_t intersect_nearest(const Tree& bvh, const RayS& ray, List& list) {
    RaySetup s;
    if (!Lanes::setup(ray, s)) return 0;
    S bound = s.tmax;
    Walk::traverse(bvh, ray, bound,
                   [&](std::size_t first, std::size_t count) SPHRAY_FORCE_INLINE_LAMBDA {
                     __builtin_prefetch(bvh.ids + first);
                     add_leaf<kMasked>(bvh, s, first, count, list);
                     if (list.full()) bound = list.last_t();
                     return false;
                   });
    return list.size();
  }

  // The crossings of the tree's leaf of count spheres at slot first, one batch of S at a time:
  // a leaf has as many slots as a float batch has lanes (bvh/box_test.hpp), and the batches
  // past its spheres hold padding alone.
  template <bool kMasked>
  SPHRAY_FORCE_INLINE static void add_leaf(const Tree& bvh, const RaySetup& s, std::size_t first,
                                           std::size_t count, List& list) {
    for (std::size_t i = first; i < first + count; i += kWidth)
      add_batch<Skip::kAfterDisc>(s, Lanes::template load_seen<kMasked>(bvh.spheres, i, s), list,
                                  [&](unsigned lane) { return bvh.ids[i + lane]; });
  }

  // The crossings of one batch: a lane's near root is an entry, its far root an exit, each
  // where it lies in (tmin, tmax). The lanes that have one are few: a loop over their bits.
  template <Skip kSkip, class IdOf>
  static void add_batch(const RaySetup& s, const Spheres& sp, List& list, IdOf id_of) {
    Floats near, far;
    Mask live;
    if (!Lanes::template near_far<kSkip>(s, sp, near, far, live)) return;
    const Floats tmax(s.tmax);
    unsigned entries = LaneReduce<A>::bits(live & (near > s.tmin) & (near < tmax));
    unsigned exits = LaneReduce<A>::bits(live & (far > s.tmin) & (far < tmax));
    if ((entries | exits) == 0) return;
    if (!list.counts_only() && list.full()) {
      // Most crossings of a long ray lie behind the kept ones: counted here, lane-parallel,
      // with no id read and no scalar comparison each.
      const Floats last(list.last_t());
      const unsigned placed_entries = entries & LaneReduce<A>::bits(near <= last);
      const unsigned placed_exits = exits & LaneReduce<A>::bits(far <= last);
      list.count(static_cast<std::size_t>(__builtin_popcount(entries ^ placed_entries) +
                                          __builtin_popcount(exits ^ placed_exits)));
      entries = placed_entries;
      exits = placed_exits;
    }
    if (list.counts_only() || (entries | exits) == 0) {
      list.count(static_cast<std::size_t>(__builtin_popcount(entries) + __builtin_popcount(exits)));
      return;
    }
    alignas(64) S near_t[kWidth], far_t[kWidth];
    near.store_aligned(near_t);
    far.store_aligned(far_t);
    for (; entries != 0; entries &= entries - 1) {
      const auto lane = static_cast<unsigned>(__builtin_ctz(entries));
      list.add(near_t[lane], id_of(lane), false);
    }
    for (; exits != 0; exits &= exits - 1) {
      const auto lane = static_cast<unsigned>(__builtin_ctz(exits));
      list.add(far_t[lane], id_of(lane), true);
    }
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
