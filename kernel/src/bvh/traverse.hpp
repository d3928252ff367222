// The SIMD walk's single-ray queries, written once over an xsimd architecture A and the scalar S
// of the tree's spheres and rays: the walk (walk.hpp: box_test.hpp per node) to each leaf the ray
// may reach, and there the leaf test (leaf_test.hpp). Each per-ISA unit instantiates it with its
// own A (dispatch/entry_points.hpp).
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "brute/sphere_lanes.hpp"
#include "bvh/bvh_data.hpp"
#include "bvh/leaf_test.hpp"
#include "bvh/walk.hpp"
#include "dispatch/query_plan.hpp"
#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct BvhTraversal {
  using Batch = SphereLanes<A, S>;
  using Data = BasicBvhData<S>;
  using Hits = BasicHit<S>;
  using Rays = BasicRay<S>;
  using Floats = typename Batch::Floats;
  using Mask = typename Batch::Mask;
  using Leaves = LeafTest<A, S>;
  using Walks = TreeWalk<A, S>;
  // Children per node and slots per leaf: a float batch's lanes (box_test.hpp).
  static constexpr std::size_t kWidth = Walks::kWidth;

  // A leaf is one aligned batch of slots: its spheres, then never-hit padding. The leaf test's
  // form (see keep_closest) is the tree's: branch-free where leaf boxes overlap.
  // Trees over spheres with masks read them at the leaves (sphere_lanes.hpp, load_seen); the
  // walk itself is the same.
  static Hits intersect(const Data& bvh, const Rays& ray) {
    const bool masked = bvh.spheres.mask != nullptr;
    if (QueryPlan::branch_free_leaves(bvh))
      return masked ? intersect<true, true>(bvh, ray) : intersect<true, false>(bvh, ray);
    return masked ? intersect<false, true>(bvh, ray) : intersect<false, false>(bvh, ray);
  }

  template <bool kBranchFree, bool kMasked>
  static Hits intersect(const Data& bvh, const Rays& ray) {
    return intersect_inlined<kBranchFree, kMasked>(bvh, ray);
  }

  // The same, inline wherever it is called: the stream's loops (bvh/stream.hpp), whichever
  // layout their rays come in. Left to itself GCC inlined intersect() into the loop over Rays
  // but not into the one over RayColumns, which ran slower; forcing it into every caller made
  // the single-ray call slower (its four forms inlined into one function). Measured in
  // docs/decisions.md, "Rays as arrays per quantity (issue 12)".
  template <bool kBranchFree, bool kMasked>
  SPHRAY_FORCE_INLINE static Hits intersect_inlined(const Data& bvh, const Rays& ray) {
    typename Batch::RaySetup s;
    Hits best{ray.tmax, kNoHit};
    if (!Batch::setup(ray, s)) return best;
    Walks::traverse(
        bvh, ray, best.t, [&](std::size_t first, std::size_t count) SPHRAY_FORCE_INLINE_LAMBDA {
          Leaves::template keep_closest<kBranchFree, kMasked>(bvh, s, first, best, count);
          return false;
        });
    return best;
  }

  static bool occluded(const Data& bvh, const Rays& ray) {
    return bvh.spheres.mask != nullptr ? occluded<true>(bvh, ray) : occluded<false>(bvh, ray);
  }

  template <bool kMasked>
  static bool occluded(const Data& bvh, const Rays& ray) {
    typename Batch::RaySetup s;
    if (!Batch::setup(ray, s)) return false;
    bool hit = false;
    Walks::traverse(bvh, ray, s.tmax,
                    [&](std::size_t first, std::size_t count) SPHRAY_FORCE_INLINE_LAMBDA {
                      hit = Leaves::template any_hit<kMasked>(bvh, s, first, count);
                      return hit;
                    });
    return hit;
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
