// The BVH traversal, written once over an xsimd architecture A: one ray against a node's
// kWidth children boxes per step, then the leaves' spheres through SphereBatchKernel<A>. Each
// per-ISA unit instantiates it with its own A (see kernel_entries.hpp).
//
// The same rule as sphere_batch.hpp holds: everything is a member of a class template over A
// and calls only builtins, intrinsics and xsimd, so units built with different flags never
// share a symbol.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "lane_reduce.hpp"
#include "sphere_batch.hpp"
#include "sphray/bvh.hpp"

namespace sphray::detail {

template <class A>
struct BvhTraversal {
  using Batch = SphereBatchKernel<A>;
  using Floats = typename Batch::Floats;
  using Mask = typename Batch::Mask;
  static constexpr std::size_t kWidth = Batch::kWidth;
  static constexpr std::size_t kNodeFloats = kBvhNodeRows * kWidth;
  // A node visit leaves at most kWidth - 1 entries above its ancestors' (one child is visited
  // next), and writes at most one slot past them: kBvhMaxDepth levels fit in this.
  static constexpr std::size_t kStackSize = kBvhMaxDepth * (kWidth - 1) + 1;

  // Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013: with every slab distance computed as
  // (plane - origin) * (1 / dir) in float, scaling the exit distance by 1 + 2 gamma(3), where
  // gamma(n) = n u / (1 - n u) and u = 2^-24, makes the box test conservative: a ray that meets
  // the box in exact arithmetic is never rejected.
  static constexpr float kGamma3 = 3.0f * 0x1p-24f / (1.0f - 3.0f * 0x1p-24f);
  static constexpr float kExitScale = 1.0f + 2.0f * kGamma3;

  // What one ray contributes to every node. near[axis] is the offset (in batches of a node's
  // box arrays) of the plane the ray meets first on that axis: lo for a positive direction, hi
  // for a negative one. An empty box (lo = +inf, hi = -inf) is then never entered.
  struct NodeSetup {
    Floats ox, oy, oz, inv_dx, inv_dy, inv_dz, tmin;
    std::size_t near_x, near_y, near_z;
  };

  struct StackEntry {
    std::uint32_t ref;
    float tnear;
  };

  static NodeSetup node_setup(const Ray& ray) {
    const Vec3& o = ray.origin;
    const Vec3& d = ray.dir;
    // A zero component gives an infinite inverse; its slab then yields +-inf, or NaN where the
    // origin lies exactly on a plane, and the NaN is ignored below.
    return {Floats(o.x),
            Floats(o.y),
            Floats(o.z),
            Floats(1.0f / d.x),
            Floats(1.0f / d.y),
            Floats(1.0f / d.z),
            Floats(ray.tmin),
            __builtin_signbit(d.x) ? 1u : 0u,
            __builtin_signbit(d.y) ? 3u : 2u,
            __builtin_signbit(d.z) ? 5u : 4u};
  }

  // max(a, b) and min(a, b) that return b when a is NaN: on x86 maxps/minps do exactly that
  // (the second operand wins), elsewhere the select does it. A NaN slab distance (0 * inf) thus
  // leaves the interval as it was: the slab is treated as unbounded, which is conservative.
  static Floats max_or_second(const Floats& a, const Floats& b) {
#if defined(__x86_64__) || defined(__i386__)
    return xsimd::max(a, b);
#else
    return xsimd::select(a > b, a, b);
#endif
  }
  static Floats min_or_second(const Floats& a, const Floats& b) {
#if defined(__x86_64__) || defined(__i386__)
    return xsimd::min(a, b);
#else
    return xsimd::select(a < b, a, b);
#endif
  }

  static Floats plane(const float* node, std::size_t array) {
    return Floats::load_aligned(node + array * kWidth);
  }

  // Rays with tmin >= 0 and direction components of normal magnitude, whose inverses are
  // finite: no slab distance can be NaN (that needs 0 * inf) and every entered box starts at
  // tnear >= 0. Nearly every ray is one (camera and scattered rays start at tmin = 0 or an
  // epsilon), and for them the box test below needs no NaN-ordered min/max chain and no sign
  // selects.
  static bool ahead(const Ray& ray) {
    constexpr float kNormal = 0x1p-126f;  // 1 / kNormal = 2^126 is finite
    return ray.tmin >= 0.0f && __builtin_fabsf(ray.dir.x) >= kNormal &&
           __builtin_fabsf(ray.dir.y) >= kNormal && __builtin_fabsf(ray.dir.z) >= kNormal;
  }

  // The children whose boxes the ray enters before best_t, and where it enters them. kAhead:
  // the ray passed ahead(); both forms return the same mask and tnear for such a ray.
  template <bool kAhead>
  static Mask enter_children(const NodeSetup& s, const float* node, const Floats& best_t,
                             Floats& tnear) {
    const Floats near_x = (plane(node, s.near_x) - s.ox) * s.inv_dx;
    const Floats near_y = (plane(node, s.near_y) - s.oy) * s.inv_dy;
    const Floats near_z = (plane(node, s.near_z) - s.oz) * s.inv_dz;
    const Floats far_x = (plane(node, s.near_x ^ 1u) - s.ox) * s.inv_dx;
    const Floats far_y = (plane(node, s.near_y ^ 1u) - s.oy) * s.inv_dy;
    const Floats far_z = (plane(node, s.near_z ^ 1u) - s.oz) * s.inv_dz;
    const Floats shrink(1.0f - 2.0f * kGamma3), grow(kExitScale);
    Floats tfar_widened;
    if constexpr (kAhead) {
      // No NaN: plain min/max, in a tree rather than a chain (the box test is on the path from
      // one node to the next). tnear >= tmin >= 0, so it shrinks; a negative tfar (a box behind
      // the origin, with an exact sign: rounding keeps it) is rejected scaled either way.
      tnear = xsimd::max(xsimd::max(near_x, near_y), xsimd::max(near_z, s.tmin)) * shrink;
      tfar_widened = xsimd::min(xsimd::min(far_x, far_y), far_z) * grow;
    } else {
      const Floats inf(__builtin_inff()), zero(0.0f);
      tnear = max_or_second(near_x, max_or_second(near_y, max_or_second(near_z, s.tmin)));
      const Floats tfar = min_or_second(far_x, min_or_second(far_y, min_or_second(far_z, inf)));
      // Ize's tnear <= tfar * (1 + 2 gamma(3)) is conservative only for tfar >= 0, but tmin
      // may be negative and boxes then lie behind the origin: widen each end by 2 gamma(3) of
      // its own magnitude instead, which holds for either sign (and keeps +-inf, never making
      // NaN).
      tnear = tnear * xsimd::select(tnear >= zero, shrink, grow);
      tfar_widened = tfar * xsimd::select(tfar >= zero, grow, shrink);
    }
    // The widened tnear is also what best_t is compared with, here and when the child is
    // popped. <= best_t, not <: a sphere at exactly best_t with a lower id still wins.
    return (tnear <= tfar_widened) & (tnear <= best_t);
  }

  static std::uint32_t child_ref(const float* node, unsigned lane) {
    return std::bit_cast<std::uint32_t>(node[6 * kWidth + lane]);
  }

  // Pushes the entered children but the nearest, farthest first, and returns the nearest: it
  // is visited next, with no trip through the stack. One or two children, what most nodes give
  // an incoherent ray, take a path without data-dependent branches.
  static std::uint32_t enter(const float* node, unsigned bits, const Floats& tnear,
                             StackEntry* stack, std::size_t& top) {
    alignas(64) float t[kWidth];
    tnear.store_aligned(t);
    const unsigned rest = bits & (bits - 1);
    if ((rest & (rest - 1)) == 0) {
      const auto a = static_cast<unsigned>(__builtin_ctz(bits));
      const auto b = rest != 0 ? static_cast<unsigned>(__builtin_ctz(rest)) : a;
      const bool b_first = t[b] <= t[a];
      const unsigned nearer = b_first ? b : a, farther = b_first ? a : b;
      // Written even for one child: the slot above top is free (see kStackSize).
      stack[top] = {child_ref(node, farther), t[farther]};
      top += rest != 0;
      return child_ref(node, nearer);
    }
    // Three or more: each child goes straight to its slot in the sorted run, its rank being
    // how many entered children precede it (farther, or as near and in a lower lane). No
    // comparison branches, only the loop over the children.
    for (unsigned left = bits; left != 0; left &= left - 1) {
      const auto lane = static_cast<unsigned>(__builtin_ctz(left));
      const Floats tl(t[lane]);
      const unsigned farther = LaneReduce<A>::bits(tnear > tl) & bits;
      const unsigned tied = LaneReduce<A>::bits(tnear == tl) & bits & ((1u << lane) - 1u);
      stack[top + static_cast<unsigned>(__builtin_popcount(farther)) +
            static_cast<unsigned>(__builtin_popcount(tied))] = {child_ref(node, lane), t[lane]};
    }
    top += static_cast<unsigned>(__builtin_popcount(bits));
    return stack[--top].ref;
  }

  // One ray's way through the tree, a leaf at a time: descend() goes from the current entry
  // down the nearest entered children to a leaf, or finds none; pop() takes the next entry off
  // the stack, skipping those behind best_t. The single-ray queries walk one ray to its end;
  // the stream can walk several in turns.
  template <bool kAhead>
  struct Walk {
    NodeSetup s;
    std::size_t top;
    std::uint32_t ref;
    StackEntry stack[kStackSize];

    void start(const Ray& ray) {
      s = node_setup(ray);
      top = 0;
      ref = 0;  // the root node
    }

    bool descend(const BvhData& bvh, float best_t, std::size_t& first) {
      while ((ref & kBvhLeafBit) == 0) {
        const float* node = bvh.nodes + std::size_t{ref} * kNodeFloats;
        Floats tnear;
        const unsigned bits =
            LaneReduce<A>::bits(enter_children<kAhead>(s, node, Floats(best_t), tnear));
        if (bits == 0) return false;
        ref = enter(node, bits, tnear, stack, top);
      }
      first = ref & kBvhLeafFirstMask & ~std::uint32_t{kWidth - 1};
      return true;
    }

    bool pop(float best_t) {
      // Entries behind the best hit so far can only hold farther spheres.
      do {
        if (top == 0) return false;
        --top;
      } while (stack[top].tnear > best_t);
      ref = stack[top].ref;
      return true;
    }

    // The first leaf after start(), if any.
    bool first_leaf(const BvhData& bvh, float best_t, std::size_t& first) {
      return descend(bvh, best_t, first) || next_leaf(bvh, best_t, first);
    }

    // The leaf after the one last returned, if any.
    bool next_leaf(const BvhData& bvh, float best_t, std::size_t& first) {
      while (pop(best_t))
        if (descend(bvh, best_t, first)) return true;
      return false;
    }
  };

  // Visits the tree: for each leaf the ray may reach before best_t, calls leaf(first sphere),
  // which returns whether to stop. Nodes are entered nearest child first.
  template <class Leaf>
  static void traverse(const BvhData& bvh, const Ray& ray, const float& best_t, Leaf&& leaf) {
    if (bvh.node_count == 0) return;
    // A tree over at most kWidth spheres is one leaf, at slot 0: it is read directly, as brute
    // force reads a batch, without a test of the root's mostly empty child boxes.
    if (bvh.count <= kWidth) {
      leaf(0);
      return;
    }
    if (ahead(ray))
      walk<true>(bvh, ray, best_t, leaf);
    else
      walk<false>(bvh, ray, best_t, leaf);
  }

  template <bool kAhead, class Leaf>
  static void walk(const BvhData& bvh, const Ray& ray, const float& best_t, Leaf& leaf) {
    Walk<kAhead> w;
    w.start(ray);
    std::size_t first;
    for (bool more = w.first_leaf(bvh, best_t, first); more; more = w.next_leaf(bvh, best_t, first))
      if (leaf(first)) return;
  }

  // A leaf is one aligned batch of slots: its spheres, then never-hit padding. The leaf test's
  // form (see keep_closest) is the tree's: branch-free where leaf boxes overlap.
  static Hit intersect(const BvhData& bvh, const Ray& ray) {
    return branch_free(bvh) ? intersect<true>(bvh, ray) : intersect<false>(bvh, ray);
  }

  template <bool kBranchFree>
  static Hit intersect(const BvhData& bvh, const Ray& ray) {
    typename Batch::RaySetup s;
    Hit best{ray.tmax, kNoHit};
    if (!Batch::setup(ray, s)) return best;
    traverse(bvh, ray, best.t, [&](std::size_t first) {
      keep_closest<kBranchFree>(bvh, s, first, best);
      return false;
    });
    return best;
  }

  // Whether the leaves take the branch-free test: where a point of the tree's box lies in
  // kBvhBranchFreeOverlap leaf boxes or more on average, a scattered ray tests several leaves, and
  // the leaf test's branches are coin tosses (see keep_closest). random:512 has 1.49,
  // random:4096 1.80, random:65536 2.09; rtiow-final 1.00 (docs/bvh.md, "Leaves").
  static bool branch_free(const BvhData& bvh) {
    return bvh.leaf_overlap >= kBvhBranchFreeOverlap;
  }

  // hits[i] = intersect(bvh, rays[i]). On a tree larger than the caches a scattered ray waits
  // on memory at nearly every node, and one ray's walk gives the core nothing else to do
  // meanwhile: there kWalks rays walk in turns, a leaf each, so that their misses overlap.
  // Elsewhere turns only add work: on a tree that fits in the caches, or for coherent rays,
  // which find the nodes their neighbours brought in (measured: docs/bvh.md, "The stream").
  // The tree's leaf test is picked once per call.
  static void intersect_stream(const BvhData& bvh, const Ray* rays, Hit* hits, std::size_t n) {
    if (branch_free(bvh))
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
          hits[i] = intersect<kBranchFree>(bvh, rays[i]);
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
        if (!ahead(rays[i])) {  // rare: one ray alone, through the general box test
          hits[i] = intersect<kBranchFree>(bvh, rays[i]);
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
        keep_closest<kBranchFree>(bvh, t.setup, t.first, t.best);
        if (t.walk.next_leaf(bvh, t.best.t, t.first)) continue;
        hits[t.ray] = t.best;
        if (!(live[k] = start(t))) --busy;
      }
    }
  }

  // Folds the hits of the leaf batch at slot i into best. Leaf order is not id order, so a tie
  // on t goes to the lower id explicitly. Two forms, the same result:
  // - kBranchFree = false: the sphere kernel's early exit when no lane's discriminant is
  //   non-negative, then a loop over the lanes that hit.
  // - kBranchFree = true: no branch on the lanes but "any hit at all": the roots of every lane,
  //   then the smallest t by a horizontal min and its id.
  // The branches win in sparse scenes, where a ray tests about one leaf and the predictor
  // learns its outcome. Scattered rays in a dense scene test several leaves, about half of
  // them with a lane whose discriminant is non-negative: there the branches are coin tosses,
  // each mispredicted one costing more than the arithmetic it skips, and coherent rays lose
  // nothing without them. The tree picks (branch_free).
  template <bool kBranchFree>
  static void keep_closest(const BvhData& bvh, const typename Batch::RaySetup& s, std::size_t i,
                           Hit& best) {
    Floats t;
    Mask live;
    constexpr Skip kSkip = kBranchFree ? Skip::kNever : Skip::kAfterDisc;
    if (!Batch::template roots<kSkip>(s, Batch::load(bvh.spheres, i), t, live)) return;
    const Mask hit = live & (t > s.tmin) & (t <= Floats(best.t));
    if constexpr (kBranchFree) {
      if (xsimd::none(hit)) return;
      const Floats m =
          LaneReduce<A>::template all_min<float>(xsimd::select(hit, t, Floats(__builtin_inff())));
      fold(best, m.get(0), lowest_id(bvh, i, LaneReduce<A>::bits(hit & (t == m))));
    } else {
      unsigned bits = LaneReduce<A>::bits(hit);
      if (bits == 0) return;
      alignas(64) float lanes[kWidth];
      t.store_aligned(lanes);
      for (; bits != 0; bits &= bits - 1) {
        const auto lane = static_cast<unsigned>(__builtin_ctz(bits));
        fold(best, lanes[lane], bvh.ids[i + lane]);
      }
    }
  }

  // The open interval: t == tmax is no hit, so a tie counts only against an earlier hit.
  static void fold(Hit& best, float t, std::uint32_t id) {
    if (t < best.t || (t == best.t && best.found() && id < best.id)) best = {t, id};
  }

  // The lowest id among the lanes of the leaf at slot i whose bits are set (at least one).
  // Several lanes share the smallest t only for equal spheres: the loop rarely runs.
  static std::uint32_t lowest_id(const BvhData& bvh, std::size_t i, unsigned lanes) {
    std::uint32_t id = bvh.ids[i + static_cast<unsigned>(__builtin_ctz(lanes))];
    for (lanes &= lanes - 1; lanes != 0; lanes &= lanes - 1) {
      const std::uint32_t other = bvh.ids[i + static_cast<unsigned>(__builtin_ctz(lanes))];
      id = other < id ? other : id;
    }
    return id;
  }

  static bool occluded(const BvhData& bvh, const Ray& ray) {
    typename Batch::RaySetup s;
    if (!Batch::setup(ray, s)) return false;
    const Floats tmax(s.tmax);
    bool hit = false;
    traverse(bvh, ray, s.tmax, [&](std::size_t first) {
      Floats t;
      Mask live;
      hit = Batch::template roots<Skip::kAfterDisc>(s, Batch::load(bvh.spheres, first), t, live) &&
            xsimd::any(live & (t > s.tmin) & (t < tmax));
      return hit;
    });
    return hit;
  }
};

}  // namespace sphray::detail
