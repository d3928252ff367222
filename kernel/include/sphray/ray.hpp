// Ray, Hit and Surface: what goes into a query and what comes out of it, in float (Ray, Hit,
// Surface) or double (Rayd, Hitd, Surfaced).
#pragma once

#include <cmath>
#include <cstdint>

#include "sphray/vec3.hpp"

namespace sphray {

/// Every bit: the default mask of rays and spheres (Ray::mask, SphereView::mask).
inline constexpr std::uint32_t kAllBits = 0xffffffffu;

/// The points origin + t * dir for tmin < t < tmax (an open interval). dir need not be unit
/// length: t is measured in units of dir. A ray with a NaN or infinite origin or direction
/// component, a zero direction, a NaN tmin or tmax, or !(tmin < tmax) misses everything.
template <Scalar S>
struct BasicRay {
  BasicVec3<S> origin;
  BasicVec3<S> dir;
  S tmin = 0;
  S tmax = INFINITY;
  /// The ray sees only the spheres whose mask shares a bit with this (SphereView::mask); a
  /// ray whose mask is 0 sees nothing.
  std::uint32_t mask = kAllBits;

  constexpr BasicVec3<S> at(S t) const { return origin + t * dir; }
};

/// The id a miss reports.
inline constexpr std::uint32_t kNoHit = 0xffffffffu;

/// Result of a closest-hit query: on a hit, the sphere's id and the ray parameter t; on a
/// miss, id == kNoHit and t == ray.tmax.
template <Scalar S>
struct BasicHit {
  S t;
  std::uint32_t id;

  constexpr bool found() const { return id != kNoHit; }
};

/// Where a ray meets a sphere: the point lies on the sphere (re-projected from the ray's t),
/// the normal is the sphere's outward unit normal there, and front_face says whether the ray
/// arrived from outside: its start, origin + tmin dir, lies outside the sphere (decided in a
/// wider type, not by the sign of dot(dir, normal), which rounding decides for grazing rays).
///
/// error bounds, coordinate by coordinate, how far the sphere's surface as any kernel computes
/// it may lie from point: the rounding of point itself and the kernel's own rounding of the
/// sphere (docs/kernel.md, "Leaving a surface"). spawn() offsets new rays by it; zero for a miss.
template <Scalar S>
struct BasicSurface {
  BasicVec3<S> point;
  BasicVec3<S> normal;
  bool front_face;
  BasicVec3<S> error{0, 0, 0};
};

using Ray = BasicRay<float>;
using Hit = BasicHit<float>;
using Surface = BasicSurface<float>;
using Rayd = BasicRay<double>;
using Hitd = BasicHit<double>;
using Surfaced = BasicSurface<double>;

}  // namespace sphray
