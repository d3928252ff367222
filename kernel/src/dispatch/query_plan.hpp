// The query plan: every choice a query makes at run time, in the order a ray meets them, in one
// place. Each is a function of what the query is given (the view's size, the tree, the ray, the
// stream), never of mutable state, and none changes a result: every path returns the same bits.
//
//   sphray::intersect(view, ray)      1. scalar loop or SIMD batches, and which width
//   sphray::intersect(tree, ray)      1. scalar walk or SIMD walk
//                                     2. the leaf test: branching or branch-free
//                                     3. the box test: rays ahead of their origin, or any ray
//                                     5. the walk, or brute force (small trees)
//   sphray::intersect(tree, rays, ..) 4. one ray at a time, or several walks in turns
//   sphray::occluded(tree, rays, ..)  6. coherent groups of rays as packets (both streams)
//                                     7. parallel rays from scattered origins sorted by their
//                                        lines into packets (both streams)
//                                     8. at a packet's leaf, rays one at a time or in lanes
//                                        (occlusion)
//   sphray::intersect(view, rays, ..) 9. one ray at a time, or the rays across the lanes
//   sphray::occluded(view, rays, ..)     (few spheres; also small trees built flat)
//
// Measured in docs/performance.md and docs/bvh.md; docs/architecture.md follows a ray through.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "bvh/bvh_data.hpp"
#include "simd/isa_namespace.hpp"
#include "sphray/ray.hpp"

namespace sphray::detail {

// 1. Views, and trees, of fewer spheres go to the scalar loop on every path: a single sphere is
// tested faster by it than by a batch that is mostly padding; from two spheres on a 4-lane batch
// wins. Larger views too small to fill two thirds of the active batch go to a narrower
// instruction set (entries_for_size, dispatch.cpp).
inline constexpr std::size_t kScalarBelow = 2;
// In double, views and trees of fewer than four spheres: with half as many lanes, a batch costs
// a double query more (its setup, the masked load of a partial batch, the reduction), and three
// spheres ran faster in the scalar loop than on every instruction set, four slower than AVX2
// and SSE4.2's full batches (docs/double.md, "Speed"; docs/history.md, "Double precision, the
// tree").
inline constexpr std::size_t kScalarBelowDouble = 4;

}  // namespace sphray::detail

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

struct QueryPlan {
  // 1. See kScalarBelow and kScalarBelowDouble.
  template <Scalar S = float>
  static bool scalar(std::size_t sphere_count) {
    return sphere_count < (std::is_same_v<S, float> ? kScalarBelow : kScalarBelowDouble);
  }

  // 2. Where a point of the tree's box lies in kBvhBranchFreeOverlap leaf boxes or more on
  // average, a scattered ray tests several leaves, and the leaf test's branches are coin
  // tosses: the tree takes the branch-free test (bvh/leaf_test.hpp). Sparse scenes such as
  // rtiow-final stay below the line and keep the branching test. The small random trees lie
  // between 1.25 and 1.5, and there the branch-free test is faster on incoherent rays and within
  // the noise on coherent ones: hence 1.25, not 1.5 (docs/bvh.md, "Leaves"; the overlaps and
  // timings: docs/history.md, "Leaves").
  template <Scalar S>
  static bool branch_free_leaves(const BasicBvhData<S>& bvh) {
    return bvh.leaf_overlap >= kBvhBranchFreeOverlap;
  }

  // 3. Rays with tmin >= 0 and direction components of normal magnitude, whose inverses are
  // finite: no slab distance can be NaN (that needs 0 * inf) and every entered box starts at
  // tnear >= 0. Nearly every ray is one (camera and scattered rays start at tmin = 0 or an
  // epsilon), and for them the box test (bvh/box_test.hpp) needs no NaN-ordered min/max chain
  // and no sign selects.
  // Float and double rays alike, each with its precision's smallest normal.
  template <Scalar S>
  static bool ahead(const BasicRay<S>& ray) {
    constexpr S kNormal = std::numeric_limits<S>::min();  // 1 / kNormal is finite
    // |x| >= kNormal without a call (std::fabs may stay a shared inline function).
    const auto normal = [](S x) { return x >= kNormal || x <= -kNormal; };
    return ray.tmin >= S(0) && normal(ray.dir.x) && normal(ray.dir.y) && normal(ray.dir.z);
  }

  // 4. On a tree larger than the caches a scattered ray waits on memory at nearly every node,
  // and one ray's walk gives the core nothing else to do meanwhile: there kWalks rays walk in
  // turns, a leaf each, so that their misses overlap (bvh/stream.hpp). Elsewhere turns only add
  // work: on a tree that fits in the caches, or for coherent rays, which find the nodes their
  // neighbours brought in (docs/bvh.md, "The stream"). Decided per chunk of kStreamChunk rays.
  static constexpr std::size_t kWalks = 4;
  static constexpr std::size_t kStreamChunk = 1024;
  static constexpr std::size_t kInTurnsAbove = std::size_t{4} << 20;
  template <class Rays>  // `const Ray*` or RayColumns (storage/ray_columns.hpp), as below
  static bool walks_in_turns(const BvhData& bvh, const Rays& rays, std::size_t n) {
    return beyond_caches(bvh) && scattered(rays, n);
  }
  // On such a tree the packets (bvh/packet.hpp) prefetch the nodes and leaves they push: it
  // made the million-sphere tree's shadow rays a little faster and left camera rays as they
  // were, but slowed rtiow-final's shadow rays on a tree that fits in the caches
  // (docs/history.md, "Shadow rays: packet leaves (issue 19, third round)").
  static bool beyond_caches(const BvhData& bvh) {
    return bvh.node_count != 0 && bvh.memory_bytes > kInTurnsAbove;
  }

  // Whether rays (a chunk of a stream) scatter: fewer than half of the neighbours' directions
  // lie within 60 degrees of each other (cosine over 1/2), judged on one pair in kSampleEvery.
  // Camera rays and mirror reflections of them nearly all do, diffuse bounces a quarter.
  static constexpr std::size_t kSampleEvery = 16;
  template <class Rays>
  static bool scattered(const Rays& rays, std::size_t n) {
    std::size_t pairs = 0, close = 0;
    for (std::size_t i = 1; i < n; i += kSampleEvery, ++pairs) {
      const Vec3 a = rays[i - 1].dir, b = rays[i].dir;
      const float ab = a.x * b.x + a.y * b.y + a.z * b.z;
      const float aa = a.x * a.x + a.y * a.y + a.z * a.z, bb = b.x * b.x + b.y * b.y + b.z * b.z;
      close += ab > 0.0f && 4.0f * ab * ab > aa * bb;  // cosine > 1/2, without sqrt or divide
    }
    return 2 * close < pairs;
  }

  // 5. A tree of at most kBvhBruteForceLeaves full leaves is built flat, its spheres in id order
  // (build.cpp), and answers as brute force on them (dispatch/entry_points.hpp): below that, a
  // scattered ray pays more for the walk's box tests, stack and mispredicted branches than for
  // the batches they skip, and the tree reads the very batches brute force reads, so it is
  // never slower than brute force on its own spheres. The limit is where the walk overtook
  // brute force on random scenes and incoherent rays, on both widths, and is in leaves rather
  // than spheres for that reason (docs/decisions.md, "The tree's instruction set, small trees
  // and `sphray bench` (issue 19)"; docs/history.md, "Small trees").
  template <Scalar S>
  static bool brute_force_tree(const BasicBvhData<S>& bvh) {
    return bvh.flat;
  }

  // 6. A packet of coherent rays tests a node's children once for all its rays, as an interval
  // ray (bvh/packet.hpp): where the rays run nearly parallel and start close together, that
  // interval is hardly wider than one ray and a node costs the packet what it costs one ray;
  // where they diverge, it enters nearly every box and the rays' own leaf-box tests do the
  // work with no culling above them. The stream judges consecutive rays kPacketRays at a time,
  // before any setup, so that a group that fails costs a few multiplications per ray: a packet
  // if at least three quarters of them (and kPacketMinRays) point within kPacketCosine of the
  // group's first ray and their origins span at most kPacketOrigins of the tree's extent.
  // Those of one octant (one near plane per axis) that are ahead then form the packet, the
  // others go one at a time (docs/bvh.md, "Packets").
  static constexpr std::size_t kPacketRays = 32;
  static constexpr std::size_t kPacketMinRays = 8;
  static constexpr float kPacketCosine = 0.97f;  // about 14 degrees
  static constexpr float kPacketOrigins = 1.0f / 64.0f;
  static bool packets(const BvhData& bvh) {
    return bvh.node_count != 0 && bvh.count > bvh.width;  // one leaf: no nodes to share
  }
  // Stops at the first ray that decides against a packet: on the groups that fail (shadow
  // rays from scattered hit points, mostly) within a few rays.
  template <class Rays>
  static bool coherent(const Rays& rays, std::size_t n, float tree_extent) {
    if (n < kPacketMinRays) return false;
    const Vec3 f = rays[0].dir;
    const float ff = f.x * f.x + f.y * f.y + f.z * f.z;
    const float limit = kPacketOrigins * tree_extent;
    const std::size_t far_allowed = n / 4;
    std::size_t far = 0;
    Vec3 lo = rays[0].origin, hi = lo;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 d = rays[i].dir, o = rays[i].origin;
      const float fd = f.x * d.x + f.y * d.y + f.z * d.z, dd = d.x * d.x + d.y * d.y + d.z * d.z;
      // The cosine over kPacketCosine without sqrt or divide; NaN compares false.
      const bool close = fd > 0.0f && fd * fd > kPacketCosine * kPacketCosine * ff * dd;
      if (!close && ++far > far_allowed) return false;
      lo = {o.x < lo.x ? o.x : lo.x, o.y < lo.y ? o.y : lo.y, o.z < lo.z ? o.z : lo.z};
      hi = {o.x > hi.x ? o.x : hi.x, o.y > hi.y ? o.y : hi.y, o.z > hi.z ? o.z : hi.z};
      if (hi.x - lo.x > limit || hi.y - lo.y > limit || hi.z - lo.z > limit) return false;
    }
    return true;
  }

  // 7. Rays that share a direction but start far apart (shadow rays towards one light from a
  // frame's hit points) fail coherent()'s origin test, yet what decides the boxes they meet is
  // their lines. The rays of a window's groups that coherent() turned down, if all but one in 8
  // at most point within kPacketCosine of the first one's, are sorted by where their lines
  // cross a plane across their main axis, and each kPacketRays of that order whose lines cross
  // it within kLineSpan of the tree's extent go as a packet (bvh/line_packet.hpp). On the sun's
  // shadow rays a tighter span leaves many more rays alone and runs slower, and no limit (every
  // group a packet) loses to 1/4 too. Groups that coherent() takes stay consecutive packets:
  // on rtiow-final's shadow rays, whose neighbours start close, line packets for whole chunks
  // ran slower. Measured in docs/history.md, "Layout, traversal and packets". Stops as soon as
  // too many rays point elsewhere.
  static constexpr float kLineSpan = 1.0f / 4.0f;
  template <class Rays>
  static bool lines(const Rays& rays, const std::uint16_t* index, std::size_t n) {
    if (n < kPacketRays) return false;
    const Vec3 f = rays[index[0]].dir;
    const float ff = f.x * f.x + f.y * f.y + f.z * f.z;
    const std::size_t far_allowed = n / 8;
    std::size_t far = 0;
    for (std::size_t j = 1; j < n; ++j) {
      const Vec3 d = rays[index[j]].dir;
      const float fd = f.x * d.x + f.y * d.y + f.z * d.z, dd = d.x * d.x + d.y * d.y + d.z * d.z;
      const bool close = fd > 0.0f && fd * fd > kPacketCosine * kPacketCosine * ff * dd;
      if (!close && ++far > far_allowed) return false;
    }
    return true;
  }

  // 7 (cont.). The occlusion stream sorts lines over windows of kLineWindow rays (four of the
  // stream's chunks), not one chunk: the denser a window's lines, the tighter its packets and
  // the fewer rays left alone; larger windows measured no faster (docs/history.md, "Layout,
  // traversal and packets"). The sort keeps 8 bytes a ray on the stack (bvh/line_packet.hpp).
  static constexpr std::size_t kLineWindow = 4096;

  // 8. At a leaf, an occlusion packet's rays that enter the leaf's box take the leaf test either
  // one ray at a time (a batch of the leaf's spheres per ray: LeafTest::any_hit) or with the
  // rays in the lanes and one sphere at a time (LeafTest::any_hit_across: a batch of rays per
  // sphere), the same answer either way. The first costs a step per ray, the second a step per
  // sphere for up to a batch of rays at once, with fewer branches. On the sun's shadow rays
  // both one ray at a time everywhere and rays in lanes everywhere ran slower than this rule,
  // and lines a little either side of it (as many rays as spheres, a quarter as many) within
  // the noise of it (docs/history.md, "Shadow rays: packet leaves (issue 19, third round)").
  static bool leaf_across(std::size_t rays, std::size_t spheres) { return 2 * rays >= spheres; }

  // 9. A stream on a view of few spheres puts its rays in the lanes, a batch of rays against
  // one broadcast sphere at a time (brute/ray_lanes.hpp), instead of one ray against batches of
  // spheres: a batch of spheres is then mostly padding, and each ray pays its set-up and the
  // horizontal reduction for a handful of sphere tests. Rays across the lanes test every sphere
  // for every ray, with no pre-test skipping the spheres far from the ray, so one ray at a time
  // wins again on larger views. kAcrossUpTo is where camera rays, the first to lose, break
  // even against the dispatched one-ray kernel; random rays gain beyond it (docs/performance.md,
  // "Rays across the lanes"). The rule does not look at the stream's length (not measured: the
  // renderer's streams are a tile's rays, hundreds at least; a stream shorter than a batch
  // leaves lanes empty). The widest instruction set takes such streams (query.cpp): it measured
  // the fastest but on the smallest views, where the 8-wide rows led on one of the two kinds of
  // rays. Same bits either way.
  static constexpr std::size_t kAcrossUpTo = 64;
  static bool rays_across(std::size_t sphere_count) { return sphere_count <= kAcrossUpTo; }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
