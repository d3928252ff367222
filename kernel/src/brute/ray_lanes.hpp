// Brute force transposed, written once over an xsimd architecture A: kWidth rays of a stream in
// the lanes of one register (4 for SSE4.2 and NEON, 8 for AVX2, 16 for AVX-512), the spheres of
// a view one at a time, each broadcast to every lane. For streams on views of few spheres, where
// one ray against a batch of spheres leaves most lanes empty and pays its set-up and horizontal
// reduction for a handful of sphere tests (QueryPlan::rays_across). Each per-ISA unit compiles it
// into its own namespace (simd/isa_namespace.hpp).
//
// The same answers bit for bit as one ray at a time (BruteForce<A>, the scalar reference): each
// lane's ray is set up with the steps of SphereLanes::setup (set_up), and each (ray, sphere)
// pair takes in its lane the very operations of SphereLanes::roots; the masks' test is an and,
// which commutes. Spheres come in id order and a lane keeps a later one only on a strictly smaller
// t, so ties go to the lower id.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#include "brute/brute_force.hpp"
#include "brute/sphere_lanes.hpp"
#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"
#include "simd/stride_gather.hpp"
#include "simd/struct_rows.hpp"
#include "sphray/ray.hpp"
#include "sphray/spheres.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct RayLanes {
  using Lanes = SphereLanes<A>;
  using Floats = typename Lanes::Floats;
  using Mask = typename Lanes::Mask;
  using Uints = typename Lanes::Uints;
  using RaySetup = typename Lanes::RaySetup;
  using Spheres = typename Lanes::Spheres;
  static constexpr std::size_t kWidth = Lanes::kWidth;

  // Up to kWidth consecutive rays of a stream, one per lane. A lane whose ray the contract
  // rejects, or past the stream's end, holds a finite dummy ray whose end is -inf: no t lies
  // below it, and it is never open.
  struct Group {
    RaySetup rays;  // ux, uy, uz unset: only the pre-test reads them, and it is not asked here
    Floats end;     // tmax, or -inf for a dummy lane
    Floats tmax;    // the rays' own, what a miss answers
    Uints masks;

    Mask open() const { return end > Floats(-__builtin_inff()); }
  };

  // The fields of up to kWidth rays, one per lane; lanes past the stream's end hold zeros.
  struct Fields {
    Floats ox, oy, oz, dx, dy, dz, tmin, tmax;
    Uints masks;
  };

  // A whole batch of rays of an array: each ray's first eight floats (origin, direction, tmin,
  // tmax) loaded as a row and the rows transposed (simd/struct_rows.hpp), the masks gathered
  // across the rays' structs (simd/stride_gather.hpp); both measured faster than copying the
  // rays one by one (docs/performance.md, "Rays across the lanes").
  static Fields fields(const Ray* rays, std::size_t count) {
    if (count < kWidth) return copied(rays, count);
    constexpr std::int32_t kStride = sizeof(Ray) / sizeof(float);
    static_assert(sizeof(Ray) == kStride * sizeof(float), "a Ray is floats and a mask");
    static_assert(offsetof(Ray, origin) == 0 && offsetof(Ray, dir) == 12 &&
                  offsetof(Ray, tmin) == 24 && offsetof(Ray, tmax) == 28);
    Floats f[8];
    StructRows<A>::first_eight(&rays[0].origin.x, kStride, f);
    return {f[0], f[1], f[2],
            f[3], f[4], f[5],
            f[6], f[7], StrideGather<A>::load(&rays[0].mask, kStride)};
  }
  // Rays as arrays per quantity, and the last rays of a stream: copied lane by lane.
  template <class Rays>
  static Fields fields(const Rays& rays, std::size_t count) {
    return copied(rays, count);
  }
  template <class Rays>
  static Fields copied(const Rays& rays, std::size_t count) {
    alignas(64) float ox[kWidth] = {}, oy[kWidth] = {}, oz[kWidth] = {};
    alignas(64) float dx[kWidth] = {}, dy[kWidth] = {}, dz[kWidth] = {};
    alignas(64) float tmin[kWidth] = {}, tmax[kWidth] = {};
    alignas(64) std::uint32_t masks[kWidth] = {};
    for (std::size_t k = 0; k < count; ++k) {
      const Ray r = rays[k];
      ox[k] = r.origin.x, oy[k] = r.origin.y, oz[k] = r.origin.z;
      dx[k] = r.dir.x, dy[k] = r.dir.y, dz[k] = r.dir.z;
      tmin[k] = r.tmin, tmax[k] = r.tmax, masks[k] = r.mask;
    }
    const auto load = [](const float* x) { return Floats::load_aligned(x); };
    return {load(ox),   load(oy),   load(oz),
            load(dx),   load(dy),   load(dz),
            load(tmin), load(tmax), Uints::load_aligned(masks)};
  }

  // The set-up of SphereLanes::setup per lane: the same squared length a, the same tests
  // (valid_line), |d| = sqrt(a) and 1/a. A mask of 0 is folded into the interval test: such a
  // ray's end is read as NaN, which fails tmin < tmax.
  template <class Rays>
  SPHRAY_FORCE_INLINE static Group set_up(const Rays& rays, std::size_t count) {
    const Fields f = fields(rays, count);
    const Uints nan_bits(0x7fc00000u);
    const Floats hi = xsimd::bitwise_cast<Floats>(
        xsimd::select(f.masks != Uints(0u), xsimd::bitwise_cast<Uints>(f.tmax), nan_bits));
    const Floats a = Lanes::squared_length(f.dx, f.dy, f.dz);
    const Mask ok = Lanes::valid_line(f.ox, f.oy, f.oz, f.dx, f.dy, f.dz, f.tmin, hi, a);
    const auto valid = [&ok](const Floats& x, float dummy) {
      return xsimd::select(ok, x, Floats(dummy));
    };
    const Floats valid_a = valid(a, 3.0f);
    return {{valid(f.ox, 0.0f), valid(f.oy, 0.0f), valid(f.oz, 0.0f), valid(f.dx, 1.0f),
             valid(f.dy, 1.0f), valid(f.dz, 1.0f), Floats(0.0f), Floats(0.0f), Floats(0.0f),
             xsimd::sqrt(valid_a), Floats(1.0f) / valid_a, valid(f.tmin, 0.0f), 0.0f, 0u},
            valid(hi, -__builtin_inff()),
            f.tmax,
            f.masks};
  }

  // Sphere j of v in every lane, made never-hit (radius 0) in the lanes whose ray cannot see it.
  template <bool kMasked>
  SPHRAY_FORCE_INLINE static Spheres broadcast(const SphereView& v, std::size_t j,
                                               const Uints& ray_masks) {
    Spheres sphere{Floats(v.cx[j]), Floats(v.cy[j]), Floats(v.cz[j]), Floats(v.radius[j])};
    if constexpr (kMasked) Lanes::hide_unseen(sphere, ray_masks, v.mask[j]);
    return sphere;
  }

  // The lanes of open that some sphere of v, ids [i, i + count), blocks strictly between their
  // tmin and end. Stops once every open lane is blocked.
  template <bool kMasked>
  SPHRAY_FORCE_INLINE static Mask any_hit(const SphereView& v, const RaySetup& rays,
                                          const Floats& end, const Uints& ray_masks, std::size_t i,
                                          std::size_t count, Mask open) {
    Mask blocked(false);
    for (std::size_t j = i; j < i + count; ++j) {
      Floats t;
      Mask live;
      const Spheres sphere = broadcast<kMasked>(v, j, ray_masks);
      if (!Lanes::template roots<Skip::kAfterDisc>(rays, sphere, t, live)) continue;
      blocked = blocked | (live & (t > rays.tmin) & (t < end));
      if (xsimd::none(open & ~blocked)) break;
    }
    return open & blocked;
  }

  // Each lane's closest hit among the spheres of v (v.count <= kNoHit): its t and id, the id
  // kNoHit where none lies in (tmin, tmax).
  template <bool kMasked>
  SPHRAY_FORCE_INLINE static void closest(const SphereView& v, const Group& g, Floats& best_t,
                                          Floats& best_id) {
    using Brute = BruteForce<A>;
    best_t = g.end;
    best_id = Brute::index_bits(kNoHit);
    for (std::size_t j = 0; j < v.count; ++j) {
      Floats t;
      Mask live;
      const Spheres sphere = broadcast<kMasked>(v, j, g.masks);
      if (!Lanes::template roots<Skip::kAfterDisc>(g.rays, sphere, t, live)) continue;
      const Mask hit = live & (t > g.rays.tmin) & (t < best_t);
      best_t = xsimd::select(hit, t, best_t);
      best_id = xsimd::select(hit, Brute::index_bits(static_cast<std::uint32_t>(j)), best_id);
    }
  }

  // hits[i] = BruteForce<A>::intersect(v, rays[i]) for i < n. Rays: `const Ray*` or RayColumns,
  // Hits: `Hit*` or HitColumns (storage/ray_columns.hpp).
  template <class Rays, class Hits>
  static void intersect_stream(SphereView v, Rays rays, Hits hits, std::size_t n) {
    v = BruteForce<A>::clamp(v);
    for (std::size_t first = 0; first < n; first += kWidth) {
      const std::size_t count = n - first < kWidth ? n - first : kWidth;
      const Group g = set_up(rays + first, count);
      Floats best_t, best_id;
      if (v.mask != nullptr)
        closest<true>(v, g, best_t, best_id);
      else
        closest<false>(v, g, best_t, best_id);
      // A lane found a sphere iff its best t went below its end; else it answers its tmax.
      const Floats answer = xsimd::select(best_t < g.end, best_t, g.tmax);
      if constexpr (std::is_same_v<Hits, Hit*>) {
        if (count == kWidth) {  // a whole batch of Hits, {t, id} each, in two or four stores
          static_assert(sizeof(Hit) == 2 * sizeof(float) && offsetof(Hit, id) == sizeof(float));
          StructRows<A>::store_pairs(hits + first, answer, best_id);
          continue;
        }
      }
      alignas(64) float t[kWidth];
      alignas(64) std::uint32_t id[kWidth];
      answer.store_aligned(t);
      xsimd::bitwise_cast<Uints>(best_id).store_aligned(id);
      for (std::size_t k = 0; k < count; ++k)
        hits[first + k] = Hit{t[k], id[k]};
    }
  }

  // blocked[i] = BruteForce<A>::occluded(v, rays[i]) for i < n.
  static void occluded_stream(SphereView v, const Ray* rays, bool* blocked, std::size_t n) {
    v = BruteForce<A>::clamp(v);
    for (std::size_t first = 0; first < n; first += kWidth) {
      const std::size_t count = n - first < kWidth ? n - first : kWidth;
      const Group g = set_up(rays + first, count);
      const Mask hit = v.mask != nullptr
                           ? any_hit<true>(v, g.rays, g.end, g.masks, 0, v.count, g.open())
                           : any_hit<false>(v, g.rays, g.end, g.masks, 0, v.count, g.open());
      const unsigned bits = LaneReduce<A>::bits(hit);
      for (std::size_t k = 0; k < count; ++k)
        blocked[first + k] = ((bits >> k) & 1u) != 0;
    }
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
