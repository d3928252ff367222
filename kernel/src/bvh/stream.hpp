// The SIMD walk's stream of rays, written once over an xsimd architecture A: one ray at a time,
// or on large trees several in turns, so that their cache misses overlap.
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "bvh/traverse.hpp"
#include "simd/isa_namespace.hpp"
#include "sphray/bvh.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct TreeStream {
  using Tree = BvhTraversal<A>;
  using Batch = typename Tree::Batch;
  using Leaves = LeafTest<A>;
  template <bool kAhead>
  using Walk = typename TreeWalk<A>::template Walk<kAhead>;

  // hits[i] = intersect(bvh, rays[i]). On a tree larger than the caches a scattered ray waits
  // on memory at nearly every node, and one ray's walk gives the core nothing else to do
  // meanwhile: there kWalks rays walk in turns, a leaf each, so that their misses overlap.
  // Elsewhere turns only add work: on a tree that fits in the caches, or for coherent rays,
  // which find the nodes their neighbours brought in (measured: docs/bvh.md, "The stream").
  // The tree's leaf test is picked once per call.
  static void intersect_stream(const BvhData& bvh, const Ray* rays, Hit* hits, std::size_t n) {
    if (Leaves::branch_free(bvh))
      intersect_stream<true>(bvh, rays, hits, n);
    else
      intersect_stream<false>(bvh, rays, hits, n);
  }

  template <bool kBranchFree>
  static void intersect_stream(const BvhData& bvh, const Ray* rays, Hit* hits, std::size_t n) {
    const bool large = bvh.node_count != 0 && bvh.memory_bytes > kInTurnsAbove;
    for (std::size_t begin = 0; begin < n; begin += kStreamChunk) {
      const std::size_t count = n - begin > kStreamChunk ? kStreamChunk : n - begin;
      if (large && scattered(rays + begin, count)) {
        intersect_in_turns<kBranchFree>(bvh, rays + begin, hits + begin, count);
      } else {
        for (std::size_t i = begin; i < begin + count; ++i)
          hits[i] = Tree::template intersect<kBranchFree>(bvh, rays[i]);
      }
    }
  }

  static constexpr std::size_t kWalks = 4;
  static constexpr std::size_t kInTurnsAbove = std::size_t{4} << 20;
  static constexpr std::size_t kStreamChunk = 1024;

  // Whether rays (a chunk of a stream) scatter: fewer than half of the neighbours' directions
  // lie within 60 degrees of each other (cosine over 1/2), judged on one pair in kSampleEvery.
  // Camera rays and mirror reflections of them nearly all do, diffuse bounces a quarter.
  static bool scattered(const Ray* rays, std::size_t n) {
    std::size_t pairs = 0, close = 0;
    for (std::size_t i = 1; i < n; i += kSampleEvery, ++pairs) {
      const Vec3 &a = rays[i - 1].dir, &b = rays[i].dir;
      const float ab = a.x * b.x + a.y * b.y + a.z * b.z;
      const float aa = a.x * a.x + a.y * a.y + a.z * a.z, bb = b.x * b.x + b.y * b.y + b.z * b.z;
      close += ab > 0.0f && 4.0f * ab * ab > aa * bb;  // cosine > 1/2, without sqrt or divide
    }
    return 2 * close < pairs;
  }
  static constexpr std::size_t kSampleEvery = 16;

  template <bool kBranchFree>
  static void intersect_in_turns(const BvhData& bvh, const Ray* rays, Hit* hits, std::size_t n) {
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
        if (!BoxTest<A>::ahead(rays[i])) {  // rare: one ray alone, through the general box test
          hits[i] = Tree::template intersect<kBranchFree>(bvh, rays[i]);
          continue;
        }
        t.best = {rays[i].tmax, kNoHit};
        if (Batch::setup(rays[i], t.setup)) {
          t.walk.start(rays[i]);
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
        Leaves::template keep_closest<kBranchFree>(bvh, t.setup, t.first, t.best);
        if (t.walk.next_leaf(bvh, t.best.t, t.first)) continue;
        hits[t.ray] = t.best;
        if (!(live[k] = start(t))) --busy;
      }
    }
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
