// The C structs and constants to and from the C++ types they mirror. sphray_ray carries no
// mask: a query's sphray_query_args give the rays' masks as an array beside them (sphray.h,
// docs/decisions.md).
#pragma once

#include <cstdint>
#include <optional>

#include "sphray/sphray.h"
#include "sphray/sphray.hpp"

namespace sphray::c_api {

inline Ray to_ray(const sphray_ray& r, std::uint32_t mask = kAllBits) {
  return {{r.ox, r.oy, r.oz}, {r.dx, r.dy, r.dz}, r.tmin, r.tmax, mask};
}

/// The i-th ray with its mask, masks being null (every bit) or one mask per ray.
inline Ray to_ray(const sphray_ray* rays, const std::uint32_t* masks, std::size_t i) {
  return to_ray(rays[i], masks == nullptr ? kAllBits : masks[i]);
}

inline sphray_ray to_c(const Ray& r) {
  return {r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax};
}

inline sphray_hit_surface to_c(const Surface& s) {
  return {s.point.x,  s.point.y, s.point.z, s.normal.x, s.normal.y,
          s.normal.z, s.error.x, s.error.y, s.error.z,  s.front_face ? 1 : 0};
}

inline Surface from_c(const sphray_hit_surface& s) {
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

inline Vec3 point_at(const float* points, std::size_t i) {
  return {points[3 * i], points[3 * i + 1], points[3 * i + 2]};
}

}  // namespace sphray::c_api
