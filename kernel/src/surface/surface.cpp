// A hit's surface (point, normal, error bound) and the origin of a ray leaving it: plain C++
// on the public types, float or double, the same on every instruction set (docs/kernel.md, "Leaving
// a surface").
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "dispatch/entry_table.hpp"
#include "sphray/isa.hpp"
#include "sphray/query.hpp"

namespace sphray {
namespace {

// The type surface() computes a hit's point and side in before rounding to S: wide enough that
// its own rounding is far below S's (float: double's 29 more bits; double: x87's 11 more bits on
// x86-64, binary128's 60 on AArch64).
template <Scalar S>
using Wider = std::conditional_t<std::is_same_v<S, float>, double, long double>;

// Higham's gamma(n) = n u / (1 - n u), u the unit roundoff of S (2^-24 for float, 2^-53 for
// double): the bound on the relative error of n chained roundings (pbrt-v4, section 6.8.1).
template <Scalar S>
constexpr S gamma(int n) {
  constexpr S u = std::numeric_limits<S>::epsilon() / 2;
  return static_cast<S>(n) * u / (S(1) - static_cast<S>(n) * u);
}

// Whether the ray's interval starts outside the sphere: in exact arithmetic, exactly when the
// hit is the near root, the side the ray arrived from. Decided in the wider type, where the
// start and the centre's difference and its square carry far less relative error than S's, not
// from the sign of dot(dir, normal): for a ray grazing a large sphere that dot product is below
// the normal's own rounding, and a ray from outside was called a back face (docs/kernel.md,
// "Front faces").
template <Scalar S>
bool starts_outside(const BasicRay<S>& ray, BasicVec3<S> center, S radius) {
  using W = Wider<S>;
  if (ray.tmin == -std::numeric_limits<S>::infinity()) return true;  // every line's near root
  const W t = ray.tmin;
  const W gx = (ray.origin.x + t * ray.dir.x) - static_cast<W>(center.x);
  const W gy = (ray.origin.y + t * ray.dir.y) - static_cast<W>(center.y);
  const W gz = (ray.origin.z + t * ray.dir.z) - static_cast<W>(center.z);
  const W r = radius;
  return gx * gx + gy * gy + gz * gz > r * r;
}

// Coordinate by coordinate, how far the sphere as a kernel computes it may lie from the point
// surface() returns, for a sphere of radius r, the point p and the unit normal n there
// (docs/kernel.md, "Leaving a surface", derives it). Two parts, in S's unit roundoff u:
// - the point: c + r n evaluated in the wider type and rounded once to S, off the sphere by at
//   most u |p_i| per coordinate (the wider type's own error is far below u r);
// - the kernels: for an origin within a few u r of the sphere they round |c - o|^2 - r^2 by
//   at most about 16 u r^2 (first order), a distance of 8 u r along the normal, whatever the
//   sphere's distance from the world origin, since they work from c - o.
// gamma(10) r along the normal and gamma(2) |p_i| bound them with a margin.
template <Scalar S>
BasicVec3<S> surface_error(BasicVec3<S> p, BasicVec3<S> n, S r) {
  const S radial = gamma<S>(10) * r;
  return {radial * std::fabs(n.x) + gamma<S>(2) * std::fabs(p.x),
          radial * std::fabs(n.y) + gamma<S>(2) * std::fabs(p.y),
          radial * std::fabs(n.z) + gamma<S>(2) * std::fabs(p.z)};
}

// The next number from x in the direction of sign (pbrt-v4's NextFloatUp/Down): rounding the
// offset origin to nearest could put it back inside the error box. std::nextafter's result for
// every x but NaN, by stepping the bits (one up the magnitude or one down) without its call:
// spawn() runs once per bounce of every path.
template <Scalar S>
S away(S x, S sign) {
  using Bits = std::conditional_t<std::is_same_v<S, float>, std::uint32_t, std::uint64_t>;
  if (sign == S(0) || std::isnan(x)) return x;
  if (x == S(0)) return std::copysign(std::numeric_limits<S>::denorm_min(), sign);  // -0 as +0
  const auto bits = std::bit_cast<Bits>(x);
  const bool grows = (x > S(0)) == (sign > S(0));
  if (!grows) return std::bit_cast<S>(static_cast<Bits>(bits - 1u));  // infinity: the largest
  return std::isinf(x) ? x : std::bit_cast<S>(static_cast<Bits>(bits + 1u));
}

template <Scalar S>
BasicSurface<S> surface_at(const BasicSphereView<S>& spheres, const BasicRay<S>& ray,
                           const BasicHit<S>& hit) {
  using W = Wider<S>;
  const BasicVec3<S> p = ray.at(hit.t);
  if (!hit.found() || hit.id >= spheres.count) return {p, {0, 0, 0}, false};
  const BasicVec3<S> center{spheres.cx[hit.id], spheres.cy[hit.id], spheres.cz[hit.id]};
  const S radius = spheres.radius[hit.id];
  // The normal from the centre, not (p - centre) / radius: p is off the sphere by t's rounding,
  // and normalising keeps the normal unit length whatever that error. The point is then put
  // back on the sphere along it, in the wider type (pbrt-v4 reprojects the same way, section
  // 6.8.5), so that its only error is its final rounding to S: in S the normal's own rounding
  // would put it some 5 u r off the sphere, which spawn() would have to step over.
  // A hit at the very centre (radius below S's resolution) has no direction from it: face
  // the ray instead, so the normal is still unit length. The squares of S's differences
  // neither underflow nor overflow in the wider type.
  const BasicVec3<S> from_center = p - center;
  const bool has_direction =
      isfinite(from_center) &&
      (from_center.x != S(0) || from_center.y != S(0) || from_center.z != S(0));
  const BasicVec3<S> toward = has_direction ? from_center : -ray.dir;
  const W x = toward.x, y = toward.y, z = toward.z;
  const W length = std::sqrt(x * x + y * y + z * z);
  const W nx = x / length, ny = y / length, nz = z / length;
  const BasicVec3<S> point{static_cast<S>(center.x + radius * nx),
                           static_cast<S>(center.y + radius * ny),
                           static_cast<S>(center.z + radius * nz)};
  const BasicVec3<S> normal{static_cast<S>(nx), static_cast<S>(ny), static_cast<S>(nz)};
  return {point, normal, starts_outside(ray, center, radius), surface_error(point, normal, radius)};
}

// pbrt-v4's OffsetRayOrigin (Physically Based Rendering, 4th ed., section 6.8.6): the error box
// projected on the normal gives the distance d along it past which no point of the box lies;
// the origin moves that far to the side dir leaves by, and each coordinate is then rounded away
// from the point so that the move survives rounding.
template <Scalar S>
BasicVec3<S> offset_from(const BasicSurface<S>& surface, BasicVec3<S> dir) {
  const BasicVec3<S> n = surface.normal;
  const S d = std::fabs(n.x) * surface.error.x + std::fabs(n.y) * surface.error.y +
              std::fabs(n.z) * surface.error.z;
  BasicVec3<S> offset = d * n;
  if (dot(dir, n) < S(0)) offset = -offset;
  const BasicVec3<S> p = surface.point + offset;
  return {away(p.x, offset.x), away(p.y, offset.y), away(p.z, offset.z)};
}

}  // namespace

Surface surface(SphereView spheres, const Ray& ray, const Hit& hit) {
  return surface_at(spheres, ray, hit);
}
Surfaced surface(SphereViewd spheres, const Rayd& ray, const Hitd& hit) {
  return surface_at(spheres, ray, hit);
}

Vec3 offset_origin(const Surface& surface, Vec3 dir) {
  return offset_from(surface, dir);
}
Vec3d offset_origin(const Surfaced& surface, Vec3d dir) {
  return offset_from(surface, dir);
}

Ray spawn(const Surface& surface, Vec3 dir) {
  return {offset_origin(surface, dir), dir, 0.0f, INFINITY};
}
Rayd spawn(const Surfaced& surface, Vec3d dir) {
  return {offset_origin(surface, dir), dir, 0.0, INFINITY};
}

namespace {
void require(bool holds, const char* what) {
  if (!holds) throw std::invalid_argument(what);
}

template <Scalar S>
bool complete(const BasicSurfaceArrays<S>& s) {
  return s.px != nullptr && s.py != nullptr && s.pz != nullptr && s.nx != nullptr &&
         s.ny != nullptr && s.nz != nullptr && s.front_face != nullptr && s.ex != nullptr &&
         s.ey != nullptr && s.ez != nullptr;
}

// surfaces()'s checks, for either precision: true when there is work.
template <Scalar S>
bool check_surfaces(const BasicRayArrays<S>& rays, const BasicHitArrays<S>& hits,
                    const BasicSurfaceArrays<S>& out) {
  if (hits.count != rays.count || out.count != rays.count)
    throw std::length_error("sphray::surfaces: rays, hits and surfaces differ in count");
  if (rays.count == 0) return false;
  require(rays.ox != nullptr && rays.oy != nullptr && rays.oz != nullptr && rays.dx != nullptr &&
              rays.dy != nullptr && rays.dz != nullptr,
          "sphray::surfaces: a ray origin or direction array is null");
  require(hits.t != nullptr && hits.id != nullptr, "sphray::surfaces: a hit array is null");
  require(complete(out), "sphray::surfaces: a surface array is null");
  return true;
}

// offset_origins()'s checks, for either precision: true when there is work.
template <Scalar S>
bool check_origins(const BasicSurfaceArrays<S>& surfaces, const BasicVectorArrays<S>& dirs,
                   const BasicVectorOutArrays<S>& origins) {
  if (dirs.count != surfaces.count || origins.count != surfaces.count)
    throw std::length_error("sphray::offset_origins: surfaces, dirs and origins differ in count");
  if (surfaces.count == 0) return false;
  require(complete(surfaces), "sphray::offset_origins: a surface array is null");
  require(dirs.x != nullptr && dirs.y != nullptr && dirs.z != nullptr,
          "sphray::offset_origins: a direction array is null");
  require(origins.x != nullptr && origins.y != nullptr && origins.z != nullptr,
          "sphray::offset_origins: an origin array is null");
  return true;
}
}  // namespace

void surfaces(SphereView spheres, const RayArrays& rays, const HitArrays& hits,
              const SurfaceArrays& out) {
  if (check_surfaces(rays, hits, out)) detail::active_entries().surfaces(spheres, rays, hits, out);
}

void offset_origins(const SurfaceArrays& surfaces, const VectorArrays& dirs,
                    const VectorOutArrays& origins) {
  if (check_origins(surfaces, dirs, origins))
    detail::active_entries().offset_origins(surfaces, dirs, origins);
}

// Double: surface() and offset_origin() one at a time, as double's other streams are.
void surfaces(SphereViewd spheres, const RayArraysd& rays, const HitArraysd& hits,
              const SurfaceArraysd& out) {
  if (!check_surfaces(rays, hits, out)) return;
  for (std::size_t i = 0; i < rays.count; ++i)
    out.set(i, surface(spheres, rays.at(i), hits.at(i)));
}

void offset_origins(const SurfaceArraysd& surfaces, const VectorArraysd& dirs,
                    const VectorOutArraysd& origins) {
  if (!check_origins(surfaces, dirs, origins)) return;
  for (std::size_t i = 0; i < surfaces.count; ++i)
    origins.set(i, offset_origin(surfaces.at(i), dirs.at(i)));
}

}  // namespace sphray
