// A hit's surface (point, normal, error bound) and the origin of a ray leaving it: plain C++
// on the public types, the same on every instruction set (docs/kernel.md, "Leaving a surface").
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "dispatch/entry_table.hpp"
#include "sphray/isa.hpp"
#include "sphray/query.hpp"

namespace sphray {
namespace {

// Higham's gamma(n) = n u / (1 - n u), u = 2^-24 the unit roundoff of float: the bound on the
// relative error of n chained roundings (pbrt-v4, section 6.8.1).
constexpr float gamma(int n) {
  constexpr float u = 0x1p-24f;
  return static_cast<float>(n) * u / (1.0f - static_cast<float>(n) * u);
}

// Whether the ray's interval starts outside the sphere: in exact arithmetic, exactly when the
// hit is the near root, the side the ray arrived from. Decided in double, where the start and
// the centre's difference and its square carry some 2^-50 of relative error, not from the sign
// of dot(dir, normal): for a ray grazing a large sphere that dot product is below the normal's
// own rounding, and a ray from outside was called a back face (docs/kernel.md, "Front faces").
bool starts_outside(const Ray& ray, Vec3 center, float radius) {
  if (ray.tmin == -INFINITY) return true;  // the near root of every line
  const double t = ray.tmin;
  const double gx = (ray.origin.x + t * ray.dir.x) - static_cast<double>(center.x);
  const double gy = (ray.origin.y + t * ray.dir.y) - static_cast<double>(center.y);
  const double gz = (ray.origin.z + t * ray.dir.z) - static_cast<double>(center.z);
  const double r = radius;
  return gx * gx + gy * gy + gz * gz > r * r;
}

// Coordinate by coordinate, how far the sphere as a kernel computes it may lie from the point
// surface() returns, for a sphere of radius r, the point p and the unit normal n there
// (docs/kernel.md, "Leaving a surface", derives it). Two parts:
// - the point: c + r n evaluated in double and rounded once to float, off the sphere by at
//   most u |p_i| per coordinate (the double's own error is some 2^-50 r);
// - the kernels: for an origin within a few u r of the sphere they round |c - o|^2 - r^2 by
//   at most about 16 u r^2 (first order), a distance of 8 u r along the normal, whatever the
//   sphere's distance from the world origin, since they work from c - o.
// gamma(10) r along the normal and gamma(2) |p_i| bound them with a margin.
Vec3 surface_error(Vec3 p, Vec3 n, float r) {
  const float radial = gamma(10) * r;
  return {radial * std::fabs(n.x) + gamma(2) * std::fabs(p.x),
          radial * std::fabs(n.y) + gamma(2) * std::fabs(p.y),
          radial * std::fabs(n.z) + gamma(2) * std::fabs(p.z)};
}

// The next float from x in the direction of sign (pbrt-v4's NextFloatUp/Down): rounding the
// offset origin to nearest could put it back inside the error box. std::nextafter's result for
// every x but NaN, by stepping the bits (one up the magnitude or one down) without its call:
// spawn() runs once per bounce of every path.
float away(float x, float sign) {
  if (sign == 0.0f || std::isnan(x)) return x;
  if (x == 0.0f) return std::copysign(0x1p-149f, sign);  // -0 steps as +0
  const auto bits = std::bit_cast<std::uint32_t>(x);
  const bool grows = (x > 0.0f) == (sign > 0.0f);
  if (!grows) return std::bit_cast<float>(bits - 1u);  // an infinity steps to the largest float
  return std::isinf(x) ? x : std::bit_cast<float>(bits + 1u);
}

}  // namespace

Surface surface(SphereView spheres, const Ray& ray, const Hit& hit) {
  const Vec3 p = ray.at(hit.t);
  if (!hit.found() || hit.id >= spheres.count) return {p, {0.0f, 0.0f, 0.0f}, false};
  const Vec3 center{spheres.cx[hit.id], spheres.cy[hit.id], spheres.cz[hit.id]};
  const float radius = spheres.radius[hit.id];
  // The normal from the centre, not (p - centre) / radius: p is off the sphere by t's rounding,
  // and normalising keeps the normal unit length whatever that error. The point is then put
  // back on the sphere along it, in double (pbrt-v4 reprojects the same way, section 6.8.5),
  // so that its only error is its final rounding to float: in float the normal's own rounding
  // would put it some 5 u r off the sphere, which spawn() would have to step over.
  // A hit at the very centre (radius below float's resolution) has no direction from it: face
  // the ray instead, so the normal is still unit length. The squares of float differences
  // neither underflow nor overflow in double.
  const Vec3 from_center = p - center;
  const bool has_direction =
      isfinite(from_center) &&
      (from_center.x != 0.0f || from_center.y != 0.0f || from_center.z != 0.0f);
  const Vec3 toward = has_direction ? from_center : -ray.dir;
  const double x = toward.x, y = toward.y, z = toward.z;
  const double length = std::sqrt(x * x + y * y + z * z);
  const double nx = x / length, ny = y / length, nz = z / length;
  const Vec3 point{static_cast<float>(center.x + radius * nx),
                   static_cast<float>(center.y + radius * ny),
                   static_cast<float>(center.z + radius * nz)};
  const Vec3 normal{static_cast<float>(nx), static_cast<float>(ny), static_cast<float>(nz)};
  return {point, normal, starts_outside(ray, center, radius), surface_error(point, normal, radius)};
}

// pbrt-v4's OffsetRayOrigin (Physically Based Rendering, 4th ed., section 6.8.6): the error box
// projected on the normal gives the distance d along it past which no point of the box lies;
// the origin moves that far to the side dir leaves by, and each coordinate is then rounded away
// from the point so that the move survives rounding.
Vec3 offset_origin(const Surface& surface, Vec3 dir) {
  const Vec3 n = surface.normal;
  const float d = std::fabs(n.x) * surface.error.x + std::fabs(n.y) * surface.error.y +
                  std::fabs(n.z) * surface.error.z;
  Vec3 offset = d * n;
  if (dot(dir, n) < 0.0f) offset = -offset;
  const Vec3 p = surface.point + offset;
  return {away(p.x, offset.x), away(p.y, offset.y), away(p.z, offset.z)};
}

Ray spawn(const Surface& surface, Vec3 dir) {
  return {offset_origin(surface, dir), dir, 0.0f, INFINITY};
}

namespace {
void require(bool holds, const char* what) {
  if (!holds) throw std::invalid_argument(what);
}

bool complete(const SurfaceArrays& s) {
  return s.px != nullptr && s.py != nullptr && s.pz != nullptr && s.nx != nullptr &&
         s.ny != nullptr && s.nz != nullptr && s.front_face != nullptr && s.ex != nullptr &&
         s.ey != nullptr && s.ez != nullptr;
}
}  // namespace

void surfaces(SphereView spheres, const RayArrays& rays, const HitArrays& hits,
              const SurfaceArrays& out) {
  if (hits.count != rays.count || out.count != rays.count)
    throw std::length_error("sphray::surfaces: rays, hits and surfaces differ in count");
  if (rays.count == 0) return;
  require(rays.ox != nullptr && rays.oy != nullptr && rays.oz != nullptr && rays.dx != nullptr &&
              rays.dy != nullptr && rays.dz != nullptr,
          "sphray::surfaces: a ray origin or direction array is null");
  require(hits.t != nullptr && hits.id != nullptr, "sphray::surfaces: a hit array is null");
  require(complete(out), "sphray::surfaces: a surface array is null");
  detail::active_entries().surfaces(spheres, rays, hits, out);
}

void offset_origins(const SurfaceArrays& surfaces, const VectorArrays& dirs,
                    const VectorOutArrays& origins) {
  if (dirs.count != surfaces.count || origins.count != surfaces.count)
    throw std::length_error("sphray::offset_origins: surfaces, dirs and origins differ in count");
  if (surfaces.count == 0) return;
  require(complete(surfaces), "sphray::offset_origins: a surface array is null");
  require(dirs.x != nullptr && dirs.y != nullptr && dirs.z != nullptr,
          "sphray::offset_origins: a direction array is null");
  require(origins.x != nullptr && origins.y != nullptr && origins.z != nullptr,
          "sphray::offset_origins: an origin array is null");
  detail::active_entries().offset_origins(surfaces, dirs, origins);
}

}  // namespace sphray
