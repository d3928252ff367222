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
  static constexpr std::size_t kNodeFloats = 8 * kWidth;
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

  // Rays with tmin >= 0 and a finite inverse of every direction component: no slab distance
  // can be NaN (that needs 0 * inf) and every entered box starts at tnear >= 0. Nearly every
  // ray is one (camera and scattered rays start at tmin = 0 or an epsilon), and for them the
  // box test below needs no NaN-ordered min/max chain and no sign selects.
  static bool ahead(const Ray& ray) {
    return ray.tmin >= 0.0f && __builtin_isfinite(1.0f / ray.dir.x) &&
           __builtin_isfinite(1.0f / ray.dir.y) && __builtin_isfinite(1.0f / ray.dir.z);
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
    const std::size_t first = top;
    for (unsigned left = bits; left != 0; left &= left - 1) {
      const auto lane = static_cast<unsigned>(__builtin_ctz(left));
      const StackEntry e{child_ref(node, lane), t[lane]};
      std::size_t i = top++;
      for (; i > first && stack[i - 1].tnear < e.tnear; --i)
        stack[i] = stack[i - 1];
      stack[i] = e;
    }
    return stack[--top].ref;
  }

  // Visits the tree: for each leaf the ray may reach before best_t, calls leaf(first sphere),
  // which returns whether to stop. Nodes are entered nearest child first.
  template <class Leaf>
  static void traverse(const BvhData& bvh, const Ray& ray, const float& best_t, Leaf&& leaf) {
    if (bvh.node_count == 0) return;
    if (ahead(ray))
      traverse_from<true>(bvh, ray, best_t, leaf);
    else
      traverse_from<false>(bvh, ray, best_t, leaf);
  }

  template <bool kAhead, class Leaf>
  static void traverse_from(const BvhData& bvh, const Ray& ray, const float& best_t, Leaf& leaf) {
    const NodeSetup s = node_setup(ray);
    StackEntry stack[kStackSize];
    std::size_t top = 0;
    std::uint32_t ref = 0;  // the root node
    for (;;) {
      if ((ref & kBvhLeafBit) == 0) {
        const float* node = bvh.nodes + std::size_t{ref} * kNodeFloats;
        Floats tnear;
        const unsigned bits =
            LaneReduce<A>::bits(enter_children<kAhead>(s, node, Floats(best_t), tnear));
        if (bits != 0) {
          ref = enter(node, bits, tnear, stack, top);
          continue;
        }
      } else if (leaf(std::size_t{ref & kBvhLeafFirstMask})) {
        return;
      }
      // Entries behind the best hit so far can only hold farther spheres.
      do {
        if (top == 0) return;
        --top;
      } while (stack[top].tnear > best_t);
      ref = stack[top].ref;
    }
  }

  // A leaf is at most kWidth spheres from its first: one batch read from there holds all of
  // them, and its other lanes the next leaf's spheres (or never-hit padding), whose hits are
  // real and may only bring the closest one in earlier.
  static Hit intersect(const BvhData& bvh, const Ray& ray) {
    typename Batch::RaySetup s;
    Hit best{ray.tmax, kNoHit};
    if (!Batch::setup(ray, s)) return best;
    traverse(bvh, ray, best.t, [&](std::size_t first) {
      keep_closest(bvh, s, first, best);
      return false;
    });
    return best;
  }

  // Folds the hits of the batch at sphere index i into best. Leaf order is not id order, so a
  // tie on t goes to the lower id explicitly.
  static void keep_closest(const BvhData& bvh, const typename Batch::RaySetup& s, std::size_t i,
                           Hit& best) {
    Floats t;
    Mask live;
    if (!Batch::roots(s, Batch::load(bvh.spheres, i), t, live)) return;
    unsigned bits = LaneReduce<A>::bits(live & (t > s.tmin) & (t <= Floats(best.t)));
    if (bits == 0) return;
    alignas(64) float lanes[kWidth];
    t.store_aligned(lanes);
    for (; bits != 0; bits &= bits - 1) {
      const auto lane = static_cast<unsigned>(__builtin_ctz(bits));
      const std::uint32_t id = bvh.ids[i + lane];
      const float tl = lanes[lane];
      // The open interval: t == tmax is no hit, so a tie counts only against an earlier hit.
      if (tl < best.t || (tl == best.t && best.found() && id < best.id)) best = {tl, id};
    }
  }

  static bool occluded(const BvhData& bvh, const Ray& ray) {
    typename Batch::RaySetup s;
    if (!Batch::setup(ray, s)) return false;
    const Floats tmax(s.tmax);
    bool hit = false;
    traverse(bvh, ray, s.tmax, [&](std::size_t first) {
      Floats t;
      Mask live;
      hit = Batch::roots(s, Batch::load(bvh.spheres, first), t, live) &&
            xsimd::any(live & (t > s.tmin) & (t < tmax));
      return hit;
    });
    return hit;
  }
};

}  // namespace sphray::detail
