// The brute-force queries over a sphere view, written once over an xsimd architecture A and a
// scalar S (float or double): the view a batch of SphereLanes<A, S> at a time, the closest hit kept
// per lane and reduced across the lanes once per ray (docs/kernel.md, "The SIMD algorithm").
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#include "brute/sphere_lanes.hpp"
#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"
#include "sphray/ray.hpp"
#include "sphray/spheres.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct BruteForce {
  using Lanes = SphereLanes<A, S>;
  using Floats = typename Lanes::Floats;
  using Mask = typename Lanes::Mask;
  using RaySetup = typename Lanes::RaySetup;
  using Spheres = typename Lanes::Spheres;
  using View = BasicSphereView<S>;
  using HitS = BasicHit<S>;
  using RayS = BasicRay<S>;
  static constexpr std::size_t kWidth = Lanes::kWidth;

  // Batch index i in a lane of S, which select() moves: in float its bits (a float holds no
  // index above 2^24 exactly), in double its value (exact up to 2^53), which the reduction can
  // then compute with.
  static Floats index_bits(std::uint32_t i) {
    if constexpr (std::is_same_v<S, float>)
      return Floats(__builtin_bit_cast(float, i));
    else
      return Floats(static_cast<S>(i));
  }

  // The horizontal step, once per ray: the smallest t over the lanes, then the lowest id among
  // the lanes that hold it (a lane's id is its batch index * width + lane). Branch-free: which
  // lanes hit is random, and a data-dependent loop over them mispredicts on most rays.
  static HitS reduce(const Floats& best_t, const Floats& best_batch, S tmax) {
    using Reduce = LaneReduce<A>;
    const Floats min_t = Reduce::template all_min<S>(best_t);
    // Lanes that never hit hold t == tmax: they are left out unless no lane hit, and that case
    // is answered below without their ids.
    const Floats candidates = xsimd::select(best_t == min_t, ids(best_batch), index_bits(kNoHit));
    const std::uint32_t id = lowest_id(candidates);
    const S t = min_t.get(0);
    return t < tmax ? HitS{t, id} : HitS{tmax, kNoHit};
  }
  // Each lane's id, batch * width + lane, kept as index_bits() keeps a batch index.
  static Floats ids(const Floats& batch) {
    using Uints = xsimd::batch<std::uint32_t, A>;
    if constexpr (std::is_same_v<S, float>) {
      return xsimd::bitwise_cast<Floats>(xsimd::bitwise_cast<Uints>(batch) * Uints(kWidth) +
                                         LaneReduce<A>::lane_index());
    } else {
      alignas(64) static constexpr S kLanes[] = {0, 1, 2, 3, 4, 5, 6, 7};
      static_assert(kWidth <= std::size(kLanes));
      return batch * Floats(static_cast<S>(kWidth)) + Floats::load_aligned(kLanes);
    }
  }
  // The smallest of the ids kept as index_bits() keeps them.
  static std::uint32_t lowest_id(const Floats& candidates) {
    using Reduce = LaneReduce<A>;
    if constexpr (std::is_same_v<S, float>) {
      using Uints = xsimd::batch<std::uint32_t, A>;
      return Reduce::template all_min<std::uint32_t>(xsimd::bitwise_cast<Uints>(candidates)).get(0);
    } else {
      // Through 64 bits: when no lane hit, the lanes hold kNoHit * width + lane, past 2^32 (and
      // the answer is a miss, whatever the id); a double's conversion to 32 bits out of range is
      // undefined, a 64-bit integer's to 32 bits wraps, as float's integer lanes do.
      const S lowest = Reduce::template all_min<S>(candidates).get(0);
      return static_cast<std::uint32_t>(static_cast<std::uint64_t>(lowest));
    }
  }

  // Batches that can be read whole: all of them if the view promises padding.
  static std::size_t whole_batches(const View& v) {
    const std::size_t rounded = (v.count + kWidth - 1) / kWidth;
    return v.padded_count >= rounded * kWidth ? rounded : v.count / kWidth;
  }

  // Ids are 32-bit with kNoHit reserved: a larger view is read as its first 2^32 - 1 spheres.
  static View clamp(View v) {
    if (v.count > kNoHit) v.count = kNoHit;
    return v;
  }

  // A view with masks takes the masked loads (sphere_lanes.hpp, load_seen); one without them,
  // exactly the loads it took before masks existed.
  //
  // The view goes by reference from here on, and is copied only when clamped: the caller
  // passed it on the stack, stored a field at a time, and a block copy of it (GCC copies with
  // vector moves) waits for those stores to retire instead of forwarding them, a stall that
  // showed in the profile of a query on a few spheres (docs/decisions.md, "Queries beyond the
  // closest hit (issue 15)").
  static HitS intersect(const View& v, const RayS& ray) {
    if (v.count > kNoHit) [[unlikely]]
      return intersect(clamp(v), ray);
    return v.mask != nullptr ? intersect<true>(v, ray) : intersect<false>(v, ray);
  }
  static bool occluded(const View& v, const RayS& ray) {
    if (v.count > kNoHit) [[unlikely]]
      return occluded(clamp(v), ray);
    return v.mask != nullptr ? occluded<true>(v, ray) : occluded<false>(v, ray);
  }

  // v.count <= kNoHit.
  template <bool kMasked>
  static HitS intersect(const View& v, const RayS& ray) {
    RaySetup s;
    if (!Lanes::setup(ray, s)) return {ray.tmax, kNoHit};
    Floats best_t(s.tmax);
    Floats best_batch = index_bits(kNoHit);
    // Strict < keeps the earlier batch (lower id) in a lane on equal t.
    auto keep = [&](const Spheres& sp, std::uint32_t batch) SPHRAY_FORCE_INLINE_LAMBDA {
      Floats t;
      Mask live;
      if (!Lanes::roots(s, sp, t, live)) return;
      const Mask hit = live & (t > s.tmin) & (t < best_t);
      best_t = xsimd::select(hit, t, best_t);
      best_batch = xsimd::select(hit, index_bits(batch), best_batch);
    };
    const std::size_t whole = whole_batches(v);
    for (std::size_t b = 0; b < whole; ++b)
      keep(Lanes::template load_seen<kMasked>(v, b * kWidth, s), static_cast<std::uint32_t>(b));
    if (whole * kWidth < v.count)
      keep(Lanes::template load_tail_seen<kMasked>(v, whole * kWidth, s),
           static_cast<std::uint32_t>(whole));
    return reduce(best_t, best_batch, ray.tmax);
  }

  template <bool kMasked>
  static bool occluded(const View& v, const RayS& ray) {
    RaySetup s;
    if (!Lanes::setup(ray, s)) return false;
    const Floats tmax(s.tmax);
    auto any_hit = [&](const Spheres& sp) SPHRAY_FORCE_INLINE_LAMBDA {
      Floats t;
      Mask live;
      return Lanes::roots(s, sp, t, live) && xsimd::any(live & (t > s.tmin) & (t < tmax));
    };
    const std::size_t whole = whole_batches(v);
    for (std::size_t b = 0; b < whole; ++b)
      if (any_hit(Lanes::template load_seen<kMasked>(v, b * kWidth, s))) return true;
    return whole * kWidth < v.count &&
           any_hit(Lanes::template load_tail_seen<kMasked>(v, whole * kWidth, s));
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
