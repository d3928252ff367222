// The C structs and constants to and from the C++ types they mirror. sphray_ray carries no
// mask: a query's sphray_query_args give the rays' masks as an array beside them (sphray.h,
// docs/decisions.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

#include "sphray/sphray.h"
#include "sphray/sphray.hpp"

namespace sphray::c_api {

/// The C structs of precision S.
template <Scalar S>
struct CTypes;
template <>
struct CTypes<float> {
  using Ray = sphray_ray;
  using Hit = sphray_hit;
  using Surface = sphray_hit_surface;
};
template <>
struct CTypes<double> {
  using Ray = sphray_ray_d;
  using Hit = sphray_hit_d;
  using Surface = sphray_hit_surface_d;
};
template <Scalar S>
using CRay = typename CTypes<S>::Ray;
template <Scalar S>
using CHit = typename CTypes<S>::Hit;
template <Scalar S>
using CSurface = typename CTypes<S>::Surface;

/// The scalar of a C struct: float for sphray_ray, double for sphray_ray_d, ...
template <class CStruct>
using ScalarOf = decltype(CStruct::tmin);

template <class CRayStruct>
BasicRay<ScalarOf<CRayStruct>> to_ray(const CRayStruct& r, std::uint32_t mask = kAllBits) {
  return {{r.ox, r.oy, r.oz}, {r.dx, r.dy, r.dz}, r.tmin, r.tmax, mask};
}

/// The i-th ray with its mask, masks being null (every bit) or one mask per ray.
template <class CRayStruct>
BasicRay<ScalarOf<CRayStruct>> to_ray(const CRayStruct* rays, const std::uint32_t* masks,
                                      std::size_t i) {
  return to_ray(rays[i], masks == nullptr ? kAllBits : masks[i]);
}

template <Scalar S>
CRay<S> to_c(const BasicRay<S>& r) {
  return {r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax};
}

template <Scalar S>
CHit<S> to_c(const BasicHit<S>& h) {
  return {h.t, h.id};
}

inline Hit from_c(const sphray_hit& h) {
  return {h.t, h.id};
}

inline Hitd from_c(const sphray_hit_d& h) {
  return {h.t, h.id};
}

template <Scalar S>
CSurface<S> to_c(const BasicSurface<S>& s) {
  return {s.point.x,  s.point.y, s.point.z, s.normal.x, s.normal.y,
          s.normal.z, s.error.x, s.error.y, s.error.z,  s.front_face ? 1 : 0};
}

template <class CSurfaceStruct>
BasicSurface<decltype(CSurfaceStruct::px)> from_c(const CSurfaceStruct& s) {
  return {{s.px, s.py, s.pz}, {s.nx, s.ny, s.nz}, s.front_face != 0, {s.ex, s.ey, s.ez}};
}

/// SPHRAY_ISA_SCALAR ... SPHRAY_ISA_NEON are the Isa enumerators in order, from 1 (0: AUTO).
static_assert(SPHRAY_ISA_SCALAR == static_cast<int>(Isa::scalar) + 1 &&
              SPHRAY_ISA_NEON == static_cast<int>(Isa::neon) + 1);

/// The Isa a SPHRAY_ISA_ value names; nothing for SPHRAY_ISA_AUTO or an unknown value.
inline std::optional<Isa> isa_from_c(int isa) {
  if (isa < SPHRAY_ISA_SCALAR || isa > SPHRAY_ISA_NEON) return std::nullopt;
  return static_cast<Isa>(isa - 1);
}

inline int to_c(Isa isa) {
  return static_cast<int>(isa) + 1;
}

template <Scalar S>
BasicVec3<S> point_at(const S* points, std::size_t i) {
  return {points[3 * i], points[3 * i + 1], points[3 * i + 2]};
}

}  // namespace sphray::c_api
