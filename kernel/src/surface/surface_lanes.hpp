// surface() and offset_origin() (surface.cpp) for a batch of hits at once, one hit per lane:
// the same operations in the same order as the one-hit functions, so that every lane gets their
// bits. Double precision where they use it, through Widen's two halves. Class template over A,
// like everything the per-ISA units include.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

#include <type_traits>

#include <xsimd/xsimd.hpp>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include "simd/isa_namespace.hpp"
#include "simd/stride_gather.hpp"
#include "simd/widen.hpp"
#include "sphray/ray_arrays.hpp"
#include "sphray/spheres.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct SurfaceLanes {
  using Floats = xsimd::batch<float, A>;
  using Bits = xsimd::batch<std::uint32_t, A>;
  using Ints = xsimd::batch<std::int32_t, A>;
  using Doubles = xsimd::batch<double, A>;
  using Mask = xsimd::batch_bool<float, A>;
  using Wide = Widen<A>;
  static constexpr std::size_t kWidth = Floats::size;

  static void surfaces(SphereView spheres, const RayArrays& rays, const HitArrays& hits,
                       const SurfaceArrays& out) {
    std::size_t i = 0;
    for (; i + kWidth <= rays.count; i += kWidth)
      surface_batch(spheres, rays, hits, out, i);
    if (i == rays.count) return;
    // The last, partial batch through full batches on the stack: the vector code's bits for
    // every lane, and no read or write past the caller's arrays.
    Tail tail;
    const std::size_t n = rays.count - i;
    const RayArrays rays_in = tail.rays(rays, i, n);
    const HitArrays hits_in = tail.hits(hits, i, n);
    const SurfaceArrays surfaces_out = tail.surfaces();
    surface_batch(spheres, rays_in, hits_in, surfaces_out, 0);
    for (std::size_t k = 0; k < n; ++k)
      out.set(i + k, surfaces_out.at(k));
  }

  static void offset_origins(const SurfaceArrays& surfaces, const VectorArrays& dirs,
                             const VectorOutArrays& origins) {
    std::size_t i = 0;
    for (; i + kWidth <= surfaces.count; i += kWidth)
      offset_batch(surfaces, dirs, origins, i);
    if (i == surfaces.count) return;
    Tail tail;
    const std::size_t n = surfaces.count - i;
    const SurfaceArrays surfaces_in = tail.surfaces(surfaces, i, n);
    const VectorArrays dirs_in = tail.dirs(dirs, i, n);
    const VectorOutArrays origins_out = tail.origins();
    offset_batch(surfaces_in, dirs_in, origins_out, 0);
    for (std::size_t k = 0; k < n; ++k)
      origins.set(i + k, {origins_out.x[k], origins_out.y[k], origins_out.z[k]});
  }

 private:
  // Higham's gamma(n) (surface.cpp's surface_error()).
  static constexpr float gamma(int n) {
    return static_cast<float>(n) * 0x1p-24f / (1.0f - static_cast<float>(n) * 0x1p-24f);
  }

  static Floats load(const float* p, std::size_t i) { return Floats::load_unaligned(p + i); }

  // Each lane's sphere (centre and radius), and whether its hit names one. A lane without a
  // sphere reads sphere 0's, if there is one, and drops it.
  struct Spheres {
    Floats cx, cy, cz, radius;
    Mask found;
  };
  static Spheres spheres_of(SphereView spheres, const std::uint32_t* ids) {
    const Bits id = Bits::load_unaligned(ids);
    const auto found = id < Bits(static_cast<std::uint32_t>(spheres.count));  // never kNoHit
    const Floats zero(0.0f);
    // As float lanes: 1.0f's bits or 0, a plain comparison with neither NaN nor subnormals.
    const Mask found_lanes =
        xsimd::bitwise_cast<Floats>(xsimd::select(found, Bits(0x3f800000u), Bits(0u))) != zero;
    if (spheres.count == 0) return {zero, zero, zero, zero, found_lanes};
    const auto at = xsimd::bitwise_cast<Ints>(xsimd::select(found, id, Bits(0u)));
    using Gather = StrideGather<A>;
    return {Gather::at(spheres.cx, at), Gather::at(spheres.cy, at), Gather::at(spheres.cz, at),
            Gather::at(spheres.radius, at), found_lanes};
  }

  // The lanes of a mask as bools.
  static void store(const Mask& lanes, bool* to) {
    const Floats one = xsimd::bitwise_cast<Floats>(Ints(1));
    const Ints ones = xsimd::bitwise_cast<Ints>(xsimd::select(lanes, one, Floats(0.0f)));
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
      _mm_storeu_si128(reinterpret_cast<__m128i*>(to), _mm512_cvtepi32_epi8(ones));
      return;
    }
#endif
    alignas(A::alignment()) std::array<std::int32_t, kWidth> values;
    ones.store_aligned(values.data());
    for (std::size_t k = 0; k < kWidth; ++k)
      to[k] = values[k] != 0;
  }

  static Floats narrow_mask(const xsimd::batch_bool<double, A>& low,
                            const xsimd::batch_bool<double, A>& high) {
    return Wide::narrow(xsimd::select(low, Doubles(1.0), Doubles(0.0)),
                        xsimd::select(high, Doubles(1.0), Doubles(0.0)));
  }

  // surface(): the normal from the centre, reprojected in double; the front face from the
  // ray's start, in double; the error bound (surface.cpp says why each is computed so).
  static void surface_batch(SphereView view, const RayArrays& rays, const HitArrays& hits,
                            const SurfaceArrays& out, std::size_t i) {
    const Floats ox = load(rays.ox, i), oy = load(rays.oy, i), oz = load(rays.oz, i);
    const Floats dx = load(rays.dx, i), dy = load(rays.dy, i), dz = load(rays.dz, i);
    const Floats t = load(hits.t, i);
    const Floats px = ox + t * dx, py = oy + t * dy, pz = oz + t * dz;  // ray.at(t)
    const Spheres s = spheres_of(view, hits.id + i);

    const Floats fx = px - s.cx, fy = py - s.cy, fz = pz - s.cz;
    const Floats largest(std::numeric_limits<float>::max());
    const Mask finite =
        (xsimd::abs(fx) <= largest) & (xsimd::abs(fy) <= largest) & (xsimd::abs(fz) <= largest);
    const Mask has_direction =
        finite & ((fx != Floats(0.0f)) | (fy != Floats(0.0f)) | (fz != Floats(0.0f)));
    const auto x = Wide::widen(xsimd::select(has_direction, fx, -dx));
    const auto y = Wide::widen(xsimd::select(has_direction, fy, -dy));
    const auto z = Wide::widen(xsimd::select(has_direction, fz, -dz));
    const auto cx = Wide::widen(s.cx), cy = Wide::widen(s.cy), cz = Wide::widen(s.cz);
    const auto r = Wide::widen(s.radius);
    const Normal low = normal(x.low, y.low, z.low, cx.low, cy.low, cz.low, r.low);
    const Normal high = normal(x.high, y.high, z.high, cx.high, cy.high, cz.high, r.high);
    const Floats nx = Wide::narrow(low.nx, high.nx), ny = Wide::narrow(low.ny, high.ny);
    const Floats nz = Wide::narrow(low.nz, high.nz);
    const Floats sx = Wide::narrow(low.px, high.px), sy = Wide::narrow(low.py, high.py);
    const Floats sz = Wide::narrow(low.pz, high.pz);

    const Floats radial = Floats(gamma(10)) * s.radius;
    const Floats g2(gamma(2));
    const Floats ex = radial * xsimd::abs(nx) + g2 * xsimd::abs(sx);
    const Floats ey = radial * xsimd::abs(ny) + g2 * xsimd::abs(sy);
    const Floats ez = radial * xsimd::abs(nz) + g2 * xsimd::abs(sz);

    const Mask front = s.found & starts_outside(rays, i, ox, oy, oz, dx, dy, dz, cx, cy, cz, r);
    const Floats zero(0.0f);
    xsimd::select(s.found, sx, px).store_unaligned(out.px + i);
    xsimd::select(s.found, sy, py).store_unaligned(out.py + i);
    xsimd::select(s.found, sz, pz).store_unaligned(out.pz + i);
    xsimd::select(s.found, nx, zero).store_unaligned(out.nx + i);
    xsimd::select(s.found, ny, zero).store_unaligned(out.ny + i);
    xsimd::select(s.found, nz, zero).store_unaligned(out.nz + i);
    store(front, out.front_face + i);
    xsimd::select(s.found, ex, zero).store_unaligned(out.ex + i);
    xsimd::select(s.found, ey, zero).store_unaligned(out.ey + i);
    xsimd::select(s.found, ez, zero).store_unaligned(out.ez + i);
  }

  struct Normal {
    Doubles nx, ny, nz, px, py, pz;
  };
  static Normal normal(const Doubles& x, const Doubles& y, const Doubles& z, const Doubles& cx,
                       const Doubles& cy, const Doubles& cz, const Doubles& r) {
    const Doubles length = xsimd::sqrt(x * x + y * y + z * z);
    const Doubles nx = x / length, ny = y / length, nz = z / length;
    return {nx, ny, nz, cx + r * nx, cy + r * ny, cz + r * nz};
  }

  using Halves = typename Wide::Halves;
  static Mask starts_outside(const RayArrays& rays, std::size_t i, const Floats& ox,
                             const Floats& oy, const Floats& oz, const Floats& dx, const Floats& dy,
                             const Floats& dz, const Halves& cx, const Halves& cy, const Halves& cz,
                             const Halves& r) {
    const Floats tmin = rays.tmin != nullptr ? load(rays.tmin, i) : Floats(0.0f);
    const auto t = Wide::widen(tmin);
    const auto wx = Wide::widen(ox), wy = Wide::widen(oy), wz = Wide::widen(oz);
    const auto vx = Wide::widen(dx), vy = Wide::widen(dy), vz = Wide::widen(dz);
    const auto outside = [](const Doubles& t, const Doubles& ox, const Doubles& oy,
                            const Doubles& oz, const Doubles& dx, const Doubles& dy,
                            const Doubles& dz, const Doubles& cx, const Doubles& cy,
                            const Doubles& cz, const Doubles& r) {
      const Doubles gx = (ox + t * dx) - cx, gy = (oy + t * dy) - cy, gz = (oz + t * dz) - cz;
      return gx * gx + gy * gy + gz * gz > r * r;
    };
    const Floats outside_lanes =
        narrow_mask(outside(t.low, wx.low, wy.low, wz.low, vx.low, vy.low, vz.low, cx.low, cy.low,
                            cz.low, r.low),
                    outside(t.high, wx.high, wy.high, wz.high, vx.high, vy.high, vz.high, cx.high,
                            cy.high, cz.high, r.high));
    // The near root of every line.
    return (tmin == Floats(-std::numeric_limits<float>::infinity())) |
           (outside_lanes != Floats(0.0f));
  }

  // offset_origin(): the error box projected on the normal, to the side dir leaves by, each
  // coordinate then stepped away from the point.
  static void offset_batch(const SurfaceArrays& s, const VectorArrays& dirs,
                           const VectorOutArrays& origins, std::size_t i) {
    const Floats nx = load(s.nx, i), ny = load(s.ny, i), nz = load(s.nz, i);
    const Floats d = xsimd::abs(nx) * load(s.ex, i) + xsimd::abs(ny) * load(s.ey, i) +
                     xsimd::abs(nz) * load(s.ez, i);
    const Floats dx = load(dirs.x, i), dy = load(dirs.y, i), dz = load(dirs.z, i);
    const Mask inward = dx * nx + dy * ny + dz * nz < Floats(0.0f);
    const Floats fx = xsimd::select(inward, -(d * nx), d * nx);
    const Floats fy = xsimd::select(inward, -(d * ny), d * ny);
    const Floats fz = xsimd::select(inward, -(d * nz), d * nz);
    away(load(s.px, i) + fx, fx).store_unaligned(origins.x + i);
    away(load(s.py, i) + fy, fy).store_unaligned(origins.y + i);
    away(load(s.pz, i) + fz, fz).store_unaligned(origins.z + i);
  }

  // surface.cpp's away(): x stepped to the next float in the direction of sign, by its bits.
  static Floats away(const Floats& x, const Floats& sign) {
    const Bits bits = xsimd::bitwise_cast<Bits>(x);
    const Floats zero(0.0f);
    // (xsimd 8.1's ^ of AVX-512 masks is an or: == instead.)
    const Mask grows = (x > zero) == (sign > zero);
    const Mask infinite = xsimd::abs(x) == Floats(std::numeric_limits<float>::infinity());
    const Floats up = xsimd::select(infinite, x, xsimd::bitwise_cast<Floats>(bits + Bits(1u)));
    const Floats down = xsimd::bitwise_cast<Floats>(bits - Bits(1u));
    const Bits sign_bit = xsimd::bitwise_cast<Bits>(sign) & Bits(0x80000000u);
    const Floats tiny = xsimd::bitwise_cast<Floats>(sign_bit | Bits(1u));  // +-2^-149
    const Floats moved = xsimd::select(x == zero, tiny, xsimd::select(grows, up, down));
    return xsimd::select((sign == zero) | (x != x), x, moved);
  }

  // Full batches on the stack for a partial one: the caller's first n values, zeros after them
  // (no sphere: a miss).
  struct Tail {
    using Lane = std::array<float, kWidth>;
    alignas(A::alignment()) std::array<Lane, 20> f{};
    alignas(A::alignment()) std::array<std::uint32_t, kWidth> id{};
    std::array<bool, kWidth> front{};

    float* copy(std::size_t slot, const float* from, std::size_t n) {
      for (std::size_t k = 0; k < n; ++k)
        f[slot][k] = from[k];
      return f[slot].data();
    }
    RayArrays rays(const RayArrays& r, std::size_t i, std::size_t n) {
      RayArrays local{copy(0, r.ox + i, n), copy(1, r.oy + i, n), copy(2, r.oz + i, n),
                      copy(3, r.dx + i, n), copy(4, r.dy + i, n), copy(5, r.dz + i, n)};
      if (r.tmin != nullptr) local.tmin = copy(6, r.tmin + i, n);
      local.count = kWidth;
      return local;
    }
    HitArrays hits(const HitArrays& h, std::size_t i, std::size_t n) {
      id.fill(std::uint32_t{kNoHit});  // a copy: binding kNoHit itself would emit it here
      for (std::size_t k = 0; k < n; ++k)
        id[k] = h.id[i + k];
      return {copy(7, h.t + i, n), id.data(), kWidth};
    }
    SurfaceArrays surfaces() {
      return {f[8].data(),  f[9].data(),  f[10].data(), f[11].data(), f[12].data(), f[13].data(),
              front.data(), f[14].data(), f[15].data(), f[16].data(), kWidth};
    }
    SurfaceArrays surfaces(const SurfaceArrays& s, std::size_t i, std::size_t n) {
      for (std::size_t k = 0; k < n; ++k)
        front[k] = s.front_face[i + k];
      return {copy(8, s.px + i, n),
              copy(9, s.py + i, n),
              copy(10, s.pz + i, n),
              copy(11, s.nx + i, n),
              copy(12, s.ny + i, n),
              copy(13, s.nz + i, n),
              front.data(),
              copy(14, s.ex + i, n),
              copy(15, s.ey + i, n),
              copy(16, s.ez + i, n),
              kWidth};
    }
    VectorArrays dirs(const VectorArrays& d, std::size_t i, std::size_t n) {
      return {copy(17, d.x + i, n), copy(18, d.y + i, n), copy(19, d.z + i, n), kWidth};
    }
    VectorOutArrays origins() { return {f[0].data(), f[1].data(), f[2].data(), kWidth}; }
  };
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
