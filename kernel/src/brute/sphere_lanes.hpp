// One ray against the spheres in the lanes of one SIMD register, written once over an xsimd
// architecture A and a scalar S: kWidth = batch<S, A>::size spheres per step (in float 4 for
// SSE4.2 and NEON, 8 for AVX2, 16 for AVX-512; in double half as many). The roots and the batch
// pre-test; brute_force.hpp loops this over a view, the tree's leaf test (bvh/leaf_test.hpp) over a
// leaf. Each per-ISA unit compiles it into its own namespace (simd/isa_namespace.hpp) and calls
// only builtins and xsimd.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#include "brute/radius_range.hpp"
#include "simd/force_inline.hpp"
#include "simd/fused.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/ordered.hpp"
#include "simd/partial_load.hpp"
#include "sphray/ray.hpp"
#include "sphray/spheres.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

// When roots() gives up on a batch none of whose lanes can hit. The brute-force loop meets
// mostly batches far from the ray, which the cheap pre-test may_hit() skips; a tree's leaves
// were reached because the ray meets their box, most pass any test, and the discriminant itself
// is then the cheaper question (docs/kernel.md, "The SIMD algorithm"); the tree's branch-free
// leaves ask nothing.
enum class Skip { kNever, kAfterDisc, kPreTest };

template <class A, class S = float>
struct SphereLanes {
  using Floats = xsimd::batch<S, A>;
  using Mask = xsimd::batch_bool<S, A>;
  // Unsigned lanes as wide as S's: the spheres' masks, widened for double.
  using Uint = std::conditional_t<sizeof(S) == 4, std::uint32_t, std::uint64_t>;
  using Uints = xsimd::batch<Uint, A>;
  using View = BasicSphereView<S>;
  static constexpr std::size_t kWidth = Floats::size;
  static constexpr bool kFloat = std::is_same_v<S, float>;

  // What one ray contributes to every batch, computed once per ray.
  struct RaySetup {
    Floats ox, oy, oz, dx, dy, dz;
    Floats ux, uy, uz;           // dir / |dir|, for may_hit only
    Floats length, inv_a, tmin;  // |dir| = sqrt(a), and 1/a with a = |dir|^2
    S tmax;
    std::uint32_t mask;
  };

  // Four SoA arrays starting at one batch.
  struct Spheres {
    Floats cx, cy, cz, r;
  };

  static bool finite(S x) { return __builtin_isfinite(x); }
  static Mask finite(const Floats& x) {
    return xsimd::abs(x) < Floats(std::numeric_limits<S>::infinity());
  }
  static S square_root(S x) {
    if constexpr (kFloat)
      return __builtin_sqrtf(x);
    else
      return __builtin_sqrt(x);
  }

  // a = |d|^2, for one ray (T = S) or one per lane (T = Floats), in one order of the sums.
  template <class T>
  SPHRAY_FORCE_INLINE static T squared_length(const T& dx, const T& dy, const T& dz) {
    return dx * dx + dy * dy + dz * dz;
  }

  // The contract's tests of a ray but its mask's, given a = |d|^2, for one ray (T = S: a truth
  // value) or one per lane (T = Floats: a Mask; brute/ray_lanes.hpp): finite origin and
  // direction, tmin < tmax, and a a normal, finite number, so that 1/a is finite too.
  template <class T>
  SPHRAY_FORCE_INLINE static auto valid_line(const T& ox, const T& oy, const T& oz, const T& dx,
                                             const T& dy, const T& dz, const T& tmin, const T& tmax,
                                             const T& a) {
    return all_of(finite(ox), finite(oy), finite(oz), finite(dx), finite(dy), finite(dz),
                  tmin < tmax, a >= T(std::numeric_limits<S>::min()), finite(a));
  }
  // Whether every truth value holds (bools), or in which lanes every mask does (Masks).
  template <class... M>
  SPHRAY_FORCE_INLINE static auto all_of(const M&... m) {
    if constexpr ((std::is_same_v<M, bool> && ...)) {
      return (m && ...);
    } else {
      return (m & ...);
    }
  }

  // False for the rays the contract says miss everything (valid_line, and a mask of 0).
  SPHRAY_FORCE_INLINE static bool setup(const BasicRay<S>& ray, RaySetup& s) {
    const BasicVec3<S>& o = ray.origin;
    const BasicVec3<S>& d = ray.dir;
    const S a = squared_length(d.x, d.y, d.z);
    const bool ok =
        valid_line(o.x, o.y, o.z, d.x, d.y, d.z, ray.tmin, ray.tmax, a) && ray.mask != 0;
    if (!ok) return false;
    const S length = square_root(a);
    const S inv_length = S(1) / length;
    s = RaySetup{Floats(o.x),
                 Floats(o.y),
                 Floats(o.z),
                 Floats(d.x),
                 Floats(d.y),
                 Floats(d.z),
                 Floats(d.x * inv_length),
                 Floats(d.y * inv_length),
                 Floats(d.z * inv_length),
                 Floats(length),
                 Floats(S(1) / a),
                 Floats(ray.tmin),
                 ray.tmax,
                 ray.mask};
    return true;
  }

  SPHRAY_FORCE_INLINE static Spheres load(const View& v, std::size_t i) {
    return {Floats::load_unaligned(v.cx + i), Floats::load_unaligned(v.cy + i),
            Floats::load_unaligned(v.cz + i), Floats::load_unaligned(v.radius + i)};
  }

  // The last count % kWidth spheres of a view that promises no padding, in a batch padded with
  // radius-0 spheres (never hit), reading nothing past the view: masked loads where the
  // instruction set has them, else a copy (simd/partial_load.hpp). Once per ray, not per batch.
  SPHRAY_FORCE_INLINE static Spheres load_tail(const View& v, std::size_t i) {
    using Partial = PartialLoad<A>;
    const std::size_t n = v.count - i;
    if constexpr (Partial::kMasked) {
      return {Partial::load(v.cx + i, n), Partial::load(v.cy + i, n), Partial::load(v.cz + i, n),
              Partial::load(v.radius + i, n)};
    } else {
      alignas(64) S x[kWidth] = {}, y[kWidth] = {}, z[kWidth] = {}, r[kWidth] = {};
      for (std::size_t k = 0; k < n; ++k) {
        x[k] = v.cx[i + k];
        y[k] = v.cy[i + k];
        z[k] = v.cz[i + k];
        r[k] = v.radius[i + k];
      }
      return {Floats::load_aligned(x), Floats::load_aligned(y), Floats::load_aligned(z),
              Floats::load_aligned(r)};
    }
  }
  SPHRAY_FORCE_INLINE static Uints load_tail_masks(const View& v, std::size_t i) {
    return load_masks(v, i, v.count - i);
  }
  // The masks of n spheres from i, zeros above (n < kWidth: a tail), as lanes of Uint.
  SPHRAY_FORCE_INLINE static Uints load_masks(const View& v, std::size_t i, std::size_t n) {
    if constexpr (kFloat) {
      if (n >= kWidth) return Uints::load_unaligned(v.mask + i);
      if constexpr (PartialLoad<A>::kMasked) return PartialLoad<A>::load(v.mask + i, n);
    }
    // Widened one by one in double (xsimd 8.1 converts integers only through memory).
    alignas(64) Uint m[kWidth] = {};
    for (std::size_t k = 0; k < n && k < kWidth; ++k)
      m[k] = v.mask[i + k];
    return Uints::load_aligned(m);
  }

  // The batch at index i of a view, its spheres the ray cannot see (their masks share no bit
  // with its own) made never-hit by a radius of 0: the root finding downstream is then the
  // unmasked one. kMasked is the view's having masks at all, decided once per query: views
  // without them take exactly the unmasked loads.
  template <bool kMasked>
  SPHRAY_FORCE_INLINE static Spheres load_seen(const View& v, std::size_t i, const RaySetup& s) {
    Spheres sp = load(v, i);
    if constexpr (kMasked) hide_unseen(sp, load_masks(v, i, kWidth), s.mask);
    return sp;
  }
  template <bool kMasked>
  SPHRAY_FORCE_INLINE static Spheres load_tail_seen(const View& v, std::size_t i,
                                                    const RaySetup& s) {
    Spheres sp = load_tail(v, i);
    if constexpr (kMasked) hide_unseen(sp, load_tail_masks(v, i), s.mask);
    return sp;
  }
  SPHRAY_FORCE_INLINE static void hide_unseen(Spheres& sp, const Uints& masks,
                                              std::uint32_t ray_mask) {
    const Uints seen = xsimd::bitwise_cast((masks & Uints(ray_mask)) != Uints(0));
    sp.r = xsimd::bitwise_cast<Floats>(xsimd::bitwise_cast<Uints>(sp.r) & seen);
  }

  // Per lane: the ray parameter t of the near root if it lies above tmin, else of the far root,
  // and whether the lane can hit at all. Returns false when no lane can: the caller skips the
  // batch (one branch per batch, not per sphere), at the point kSkip says. Skip::kNever
  // computes the roots whatever the lanes and always returns true, for callers to whom that
  // branch is a coin toss (the BVH on scattered rays).
  //
  // Precision (Haines, Guenther, Akenine-Moeller, "Precision Improvements for Ray/Sphere
  // Intersection", Ray Tracing Gems ch. 7): with g = centre - origin (= -f), b' = g.d and
  // k = b'/a, the discriminant is taken in its perpendicular form disc = r^2 - |k d - g|^2,
  // which does not lose the small difference b'^2 - a c to cancellation, and the roots as
  // c/q and q/a with q = b' + sign(b') sqrt(a) sqrt(disc), which never subtracts nearly equal
  // values. sqrt(a) sqrt(disc), not sqrt(a disc): the product a disc overflows float for long
  // directions and large spheres (|dir| = 1e18, r = 1e10), and underflows for short directions
  // and tiny spheres, where q = |dir| sqrt(disc) itself is an ordinary float; sqrt(a) is taken
  // once per ray, so a lane still takes one square root.
  //
  // c is not |g|^2 - r^2 but k b' - disc, its value in exact arithmetic, taken from the disc
  // just computed: the roots are then k -+ sqrt(disc/a) up to a few roundings, two points of
  // the line at squared distance |k d - g|^2 + disc = r^2 from the centre. Computed on its own,
  // |g|^2 - r^2 carries a rounding error of u |g|^2 that disc does not share, and for an origin
  // on the sphere and a ray leaving it tangentially (q tiny) c / q put "hits" tens of radii off
  // the sphere (docs/kernel.md, "Where a hit can lie").
  //
  // No fused multiply-add, and every sum in one fixed order: every instruction set, and the
  // scalar reference (scalar.cpp), make the same roundings and return the same bits.
  template <Skip kSkip = Skip::kPreTest>
  SPHRAY_FORCE_INLINE static bool roots(const RaySetup& s, const Spheres& sp, Floats& t,
                                        Mask& live) {
    Floats near, far;
    if (!near_far<kSkip>(s, sp, near, far, live)) return false;
    t = xsimd::select(near > s.tmin, near, far);
    return true;
  }

  // Both roots per lane, near <= far, for the queries that want every crossing (all_hits/):
  // the same operations as roots(), which takes one of them.
  template <Skip kSkip = Skip::kPreTest>
  SPHRAY_FORCE_INLINE static bool near_far(const RaySetup& s, const Spheres& sp, Floats& near,
                                           Floats& far, Mask& live) {
    const Floats gx = sp.cx - s.ox, gy = sp.cy - s.oy, gz = sp.cz - s.oz;
    if (kSkip == Skip::kPreTest && !may_hit(s, sp, gx, gy, gz)) return false;
    const Floats b = gx * s.dx + (gy * s.dy + gz * s.dz);
    const Floats k = b * s.inv_a;
    const Floats vx = k * s.dx - gx, vy = k * s.dy - gy, vz = k * s.dz - gz;
    const Floats disc = sp.r * sp.r - (vx * vx + (vy * vy + vz * vz));
    // NaN and infinite sphere fields make disc NaN (infinite centre: inf - inf in v), which
    // fails the test; a radius of 2^64 or more makes r^2 infinite and the roots +-inf or NaN,
    // never inside (tmin, tmax). A radius below kMinRadius (<= 0 included) needs its own: its
    // square underflows, and with |v|^2 underflowing too disc is 0 far from the sphere.
    live = disc >= Floats(S(0));
    if (kSkip == Skip::kAfterDisc && xsimd::none(live)) return false;
    live = live & (sp.r >= Floats(RadiusRange<S>::kMin));
    const Floats c = k * b - disc;
    const Floats q = b + with_sign_of(s.length * xsimd::sqrt(disc), b);
    const Floats t0 = c / q, t1 = q * s.inv_a;
    // t0 is NaN only for 0/0 (origin on the sphere, tangent), and then both roots are t1.
    using O = Ordered<A, S>;
    near = O::less_or_second(t0, t1);
    far = O::greater_or_second(t0, t1);
    return true;
  }

  // False only if no lane of the batch can have disc >= 0 in roots(): a cheaper test that lets
  // most batches of a scene be skipped, with fused operations where the instruction set has
  // them (it decides no result, only which batches are computed). It compares the squared
  // distance from the centre to the line, |g|^2 - (g.u)^2 with u the unit direction, against
  // r^2 widened by kMayHitMargin (|g|^2 + r^2): that form cancels, but its error is below
  // 19 u |g|^2, and roots()' disc errs by less than 13 u r^2 + 8 u |g|^2 (docs/kernel.md, "The
  // SIMD algorithm"); kMayHitSlack covers underflow. NaN lanes pass.
  // In float 64 u = 64 * 2^-24 and 2^-120 (64 FLT_MIN); in double the same in its u and min.
  static constexpr S kMayHitMargin = 64 * (std::numeric_limits<S>::epsilon() / 2);
  static constexpr S kMayHitSlack = 64 * std::numeric_limits<S>::min();
  SPHRAY_FORCE_INLINE static bool may_hit(const RaySetup& s, const Spheres& sp, const Floats& gx,
                                          const Floats& gy, const Floats& gz) {
    using F = Fused<A, S>;
    const Floats gg = F::fma(gx, gx, F::fma(gy, gy, gz * gz));
    const Floats gu = F::fma(gx, s.ux, F::fma(gy, s.uy, gz * s.uz));
    const Floats r2 = sp.r * sp.r;
    const Floats bound = r2 + F::fma(Floats(kMayHitMargin), gg + r2, Floats(kMayHitSlack));
    return !xsimd::all(F::fnma(gu, gu, gg) > bound);
  }

  // copysign(x, b) for x >= 0 (a square root; in a lane that cannot hit, any value), written
  // out: xsimd's copysign calls a function templated on float only, one symbol for every unit
  // (simd/isa_namespace.hpp).
  SPHRAY_FORCE_INLINE static Floats with_sign_of(const Floats& x, const Floats& b) {
    return x | (b & Floats(S(-0.0)));
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
