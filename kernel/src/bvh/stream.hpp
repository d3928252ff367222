// The SIMD walk's stream of rays, written once over an xsimd architecture A: coherent rays in
// packets, the others one ray at a time, or on large trees several in turns, so that their
// cache misses overlap.
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "bvh/bvh_data.hpp"
#include "bvh/packet_stream.hpp"
#include "bvh/traverse.hpp"
#include "dispatch/query_plan.hpp"
#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"
#include "storage/ray_columns.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct TreeStream {
  using Tree = BvhTraversal<A>;
  using Batch = typename Tree::Batch;
  using Leaves = LeafTest<A>;
  using Plan = QueryPlan;
  template <bool kAhead>
  using Walk = typename TreeWalk<A>::template Walk<kAhead>;

  // hits[i] = intersect(bvh, rays[i]): a chunk of rays in turns, in packets, or one at a time,
  // as the plan says. The tree's leaf test is picked once per call. Rays is `const Ray*` or
  // RayColumns, Hits `Hit*` or HitColumns (storage/ray_columns.hpp): the same path either way.
  template <class Rays, class Hits>
  static void intersect_stream(const BvhData& bvh, Rays rays, Hits hits, std::size_t n) {
    const bool masked = bvh.spheres.mask != nullptr;
    if (Plan::branch_free_leaves(bvh)) {
      if (masked)
        intersect_stream<true, true>(bvh, rays, hits, n);
      else
        intersect_stream<true, false>(bvh, rays, hits, n);
    } else {
      if (masked)
        intersect_stream<false, true>(bvh, rays, hits, n);
      else
        intersect_stream<false, false>(bvh, rays, hits, n);
    }
  }

  template <bool kBranchFree, bool kMasked, class Rays, class Hits>
  static void intersect_stream(const BvhData& bvh, Rays rays, Hits hits, std::size_t n) {
    constexpr std::size_t kChunk = Plan::kStreamChunk;
    for (std::size_t begin = 0; begin < n; begin += kChunk) {
      const std::size_t count = n - begin > kChunk ? kChunk : n - begin;
      if (Plan::walks_in_turns(bvh, rays + begin, count)) {
        intersect_in_turns<kBranchFree, kMasked>(bvh, rays + begin, hits + begin, count);
      } else if (Plan::packets(bvh) && !Plan::scattered(rays + begin, count)) {
        PacketStream<A>::template intersect<kBranchFree, kMasked>(bvh, rays + begin, hits + begin,
                                                                  count);
      } else {
        one_at_a_time<kBranchFree, kMasked>(bvh, rays + begin, hits + begin, count);
      }
    }
  }

  template <bool kBranchFree, bool kMasked, class Hits>
  static void one_at_a_time(const BvhData& bvh, const Ray* rays, Hits hits, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
      hits[i] = Tree::template intersect_inlined<kBranchFree, kMasked>(bvh, rays[i]);
  }
  // Rays given as arrays are copied into Rays a few at a time before their walks: the walk
  // reads its Ray through memory, and a Ray stored just before is read back at a cost.
  template <bool kBranchFree, bool kMasked, class Hits>
  static void one_at_a_time(const BvhData& bvh, const RayColumns& rays, Hits hits, std::size_t n) {
    constexpr std::size_t kStaged = 16;
    Ray staged[kStaged];
    for (std::size_t begin = 0; begin < n; begin += kStaged) {
      const std::size_t m = n - begin < kStaged ? n - begin : kStaged;
      for (std::size_t j = 0; j < m; ++j)
        staged[j] = rays[begin + j];
      for (std::size_t j = 0; j < m; ++j)
        hits[begin + j] = Tree::template intersect_inlined<kBranchFree, kMasked>(bvh, staged[j]);
    }
  }

  // blocked[i] = occluded(bvh, rays[i]): coherent rays (shadow rays towards one light) in
  // packets, the others one at a time. Decided per window of QueryPlan::kLineWindow rays, the
  // line packets' sort window.
  template <class Rays>
  static void occluded_stream(const BvhData& bvh, Rays rays, bool* blocked, std::size_t n) {
    if (bvh.spheres.mask != nullptr)
      occluded_stream<true>(bvh, rays, blocked, n);
    else
      occluded_stream<false>(bvh, rays, blocked, n);
  }

  template <bool kMasked, class Rays>
  static void occluded_stream(const BvhData& bvh, Rays rays, bool* blocked, std::size_t n) {
    constexpr std::size_t kWindow = Plan::kLineWindow;
    for (std::size_t begin = 0; begin < n; begin += kWindow) {
      const std::size_t count = n - begin > kWindow ? kWindow : n - begin;
      if (Plan::packets(bvh) && !Plan::scattered(rays + begin, count)) {
        PacketStream<A>::template occluded<kMasked>(bvh, rays + begin, blocked + begin, count);
      } else {
        for (std::size_t i = begin; i < begin + count; ++i)
          blocked[i] = Tree::template occluded<kMasked>(bvh, rays[i]);
      }
    }
  }

  static constexpr std::size_t kWalks = Plan::kWalks;

  template <bool kBranchFree, bool kMasked, class Rays, class Hits>
  static void intersect_in_turns(const BvhData& bvh, Rays rays, Hits hits, std::size_t n) {
    struct Turn {
      Walk<true> walk;
      typename Batch::RaySetup setup;
      Hit best;
      std::size_t ray, first;
    };
    Turn turns[kWalks];
    bool live[kWalks];
    std::size_t next = 0, busy = 0;
    // Starts t on the next ray that reaches a leaf; the others are answered at once.
    const auto start = [&](Turn& t) {
      while (next < n) {
        const std::size_t i = next++;
        const auto& ray = rays[i];  // a Ray of the array, or one made from RayColumns
        if (!Plan::ahead(ray)) {    // rare: one ray alone, through the general box test
          hits[i] = Tree::template intersect_inlined<kBranchFree, kMasked>(bvh, ray);
          continue;
        }
        t.best = {ray.tmax, kNoHit};
        if (Batch::setup(ray, t.setup)) {
          t.walk.start(ray);
          if (t.walk.first_leaf(bvh, t.best.t, t.first)) {
            t.ray = i;
            return true;
          }
        }
        hits[i] = t.best;
      }
      return false;
    };
    for (std::size_t k = 0; k < kWalks; ++k)
      busy += (live[k] = start(turns[k]));
    while (busy != 0) {
      for (std::size_t k = 0; k < kWalks; ++k) {
        if (!live[k]) continue;
        Turn& t = turns[k];
        Leaves::template keep_closest<kBranchFree, kMasked>(bvh, t.setup, t.first, t.best);
        if (t.walk.next_leaf(bvh, t.best.t, t.first)) continue;
        hits[t.ray] = t.best;
        if (!(live[k] = start(t))) --busy;
      }
    }
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
