// The point queries, written once over an xsimd architecture A and the scalar S: the sphere
// nearest a point (by signed distance to its surface) and the spheres a query ball overlaps,
// over a view a batch at a time, or through a tree by distance (bvh/distance_walk.hpp):
// children nearest first, and a child skipped once its box's lower bound is beyond what is
// still wanted.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

#include <xsimd/xsimd.hpp>

#include "brute/brute_force.hpp"
#include "brute/sphere_lanes.hpp"
#include "bvh/bvh_data.hpp"
#include "bvh/distance_walk.hpp"
#include "point/id_collector.hpp"
#include "point/point_lanes.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct PointQueries {
  using Lanes = PointLanes<A, S>;
  using Floats = typename Lanes::Floats;
  using Mask = typename Lanes::Mask;
  using Point = typename Lanes::Point;
  using Spheres = typename Lanes::Spheres;
  using Sphere = SphereLanes<A, S>;
  using Brute = BruteForce<A, S>;
  using Walk = DistanceWalk<A, S>;
  using Data = BasicBvhData<S>;
  using View = BasicSphereView<S>;
  using Vec = BasicVec3<S>;
  using HitS = BasicHit<S>;
  static constexpr std::size_t kLanes = Lanes::kWidth;
  // A tree's leaf: kWidth slots, kPieces batches of S (box_test.hpp).
  static constexpr std::size_t kWidth = Walk::kWidth;
  static constexpr std::size_t kPieces = kWidth / kLanes;
  static constexpr S kInf = std::numeric_limits<S>::infinity();

  static bool finite(Vec p) {
    return __builtin_isfinite(p.x) && __builtin_isfinite(p.y) && __builtin_isfinite(p.z);
  }

  // The nearest sphere as (signed distance, id): the smallest distance, then the lowest id, of
  // the valid spheres at a finite distance; {+inf, kNoHit} if none. The caller applies the
  // query's maximum.
  static HitS nearest(View v, Vec point) {
    if (!finite(point)) return {kInf, kNoHit};
    v = Brute::clamp(v);
    const Point p = Lanes::setup(point);
    Floats best_d(kInf);
    Floats best_batch = Brute::index_bits(kNoHit);
    auto keep = [&](const Spheres& sp, std::uint32_t batch) {
      Mask valid;
      const Floats d = Lanes::signed_distance(p, sp, valid);
      const Mask nearer = valid & (d < best_d);  // strict: the earlier batch keeps a tie
      best_d = xsimd::select(nearer, d, best_d);
      best_batch = xsimd::select(nearer, Brute::index_bits(batch), best_batch);
    };
    const std::size_t whole = Brute::whole_batches(v);
    for (std::size_t b = 0; b < whole; ++b)
      keep(Sphere::load(v, b * kLanes), static_cast<std::uint32_t>(b));
    if (whole * kLanes < v.count)
      keep(Sphere::load_tail(v, whole * kLanes), static_cast<std::uint32_t>(whole));
    return Brute::reduce(best_d, best_batch, kInf);
  }

  // The spheres whose signed distance from centre is below radius, into out (or only whether
  // there is one, when out.first_only). Returns out.total.
  static std::size_t overlapping(View v, Vec centre, S radius, IdCollector& out) {
    if (!finite(centre) || !(radius >= S(0))) return 0;
    v = Brute::clamp(v);
    const Point p = Lanes::setup(centre);
    const Floats limit(radius);
    auto add = [&](const Spheres& sp, std::size_t first) {
      Mask valid;
      const Floats d = Lanes::signed_distance(p, sp, valid);
      unsigned bits = LaneReduce<A>::bits(valid & (d < limit));
      for (; bits != 0; bits &= bits - 1)
        if (out.add(static_cast<std::uint32_t>(first + static_cast<unsigned>(__builtin_ctz(bits)))))
          return true;
      return false;
    };
    const std::size_t whole = Brute::whole_batches(v);
    for (std::size_t b = 0; b < whole; ++b)
      if (add(Sphere::load(v, b * kLanes), b * kLanes)) return out.total;
    if (whole * kLanes < v.count) add(Sphere::load_tail(v, whole * kLanes), whole * kLanes);
    return out.total;
  }

  // slot: where the answer sits in bvh.spheres.
  static HitS nearest(const Data& bvh, Vec point, S max_distance, std::size_t& slot) {
    HitS best{kInf, kNoHit};
    if (!finite(point)) return best;
    const Point p = Lanes::setup(point);
    // What a child's bound must not exceed: the best so far, and never beyond the maximum.
    auto bound = [&] { return best.t < max_distance ? best.t : max_distance; };
    Walk::visit(bvh, p.x, p.y, p.z, bound, [&](std::size_t first) {
      for (std::size_t piece = 0; piece < kPieces; ++piece)
        keep_nearest(bvh, p, first + piece * kLanes, best, slot);
      return false;
    });
    return best;
  }

  static std::size_t overlapping(const Data& bvh, Vec centre, S radius, IdCollector& out) {
    if (!finite(centre) || !(radius >= S(0))) return 0;
    const Point p = Lanes::setup(centre);
    const Floats limit(radius);
    Walk::visit(
        bvh, p.x, p.y, p.z, [&] { return radius; },
        [&](std::size_t first) {
          for (std::size_t at = first; at < first + kWidth; at += kLanes) {
            Mask valid;
            const Floats d = Lanes::signed_distance(p, Sphere::load(bvh.spheres, at), valid);
            unsigned bits = LaneReduce<A>::bits(valid & (d < limit));
            for (; bits != 0; bits &= bits - 1)
              if (out.add(bvh.ids[at + static_cast<unsigned>(__builtin_ctz(bits))])) return true;
          }
          return false;
        });
    return out.total;
  }

 private:
  // The batch of a leaf at slot `first` against best, which it replaces if it holds a sphere
  // nearer (or as near with a lower id). The slots of a leaf are not in id order.
  static void keep_nearest(const Data& bvh, const Point& p, std::size_t first, HitS& best,
                           std::size_t& slot) {
    Mask valid;
    const Floats d = Lanes::signed_distance(p, Sphere::load(bvh.spheres, first), valid);
    const Mask live = valid & (d <= Floats(best.t));
    if (xsimd::none(live)) return;
    const Floats m = LaneReduce<A>::template all_min<S>(xsimd::select(live, d, Floats(kInf)));
    const S dm = m.get(0);
    if (!(dm < kInf)) return;
    const std::size_t at = first + lowest_id_lane(bvh, first, LaneReduce<A>::bits(live & (d == m)));
    const HitS candidate{dm, bvh.ids[at]};
    if (candidate.t < best.t || (candidate.t == best.t && candidate.id < best.id)) {
      best = candidate;
      slot = at;
    }
  }

  // The lane of the lowest id among the batch's set lanes (at least one; several only for
  // spheres at exactly the same distance).
  static unsigned lowest_id_lane(const Data& bvh, std::size_t first, unsigned lanes) {
    auto lane = static_cast<unsigned>(__builtin_ctz(lanes));
    for (lanes &= lanes - 1; lanes != 0; lanes &= lanes - 1) {
      const auto other = static_cast<unsigned>(__builtin_ctz(lanes));
      if (bvh.ids[first + other] < bvh.ids[first + lane]) lane = other;
    }
    return lane;
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
