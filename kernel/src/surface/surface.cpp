// A hit's surface (point, normal, error bound) and the origin of a ray leaving it: plain C++
// on the public types, the same on every instruction set (docs/kernel.md, "Leaving a surface").
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "sphray/query.hpp"

namespace sphray {
namespace {

// Higham's gamma(n) = n u / (1 - n u), u = 2^-24 the unit roundoff of float: the bound on the
// relative error of n chained roundings (pbrt-v4, section 6.8.1).
constexpr float gamma(int n) {
  constexpr float u = 0x1p-24f;
  return static_cast<float>(n) * u / (1.0f - static_cast<float>(n) * u);
}

// Coordinate by coordinate, how far the surface as a kernel computes it may be from the point
// surface() returns, for a sphere of centre c and radius r (docs/kernel.md, "Leaving a surface",
// derives it). The point c + r n is rounded in its normal's normalisation (6 roundings of n's
// length, hence of the radius along n), its product with r and its sum with c: gamma(8) of
// |c_i| + r covers them. A kernel rounds c - origin and squares it against r^2 in c and in
// the discriminant: as a distance along the normal, gamma(7) r. gamma(16) leaves each part
// room to spare; the offset it costs is 1e-6 of the scene's scale.
Vec3 surface_error(Vec3 c, float r) {
  return gamma(16) * Vec3{std::fabs(c.x) + r, std::fabs(c.y) + r, std::fabs(c.z) + r};
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

// A power of two s with s * x in [1, 4) for finite x > 0 (in [2^-22, 4) for denormals): a
// scale by it is exact, where a division by x would round, and costs a multiply, not a divide.
float power_of_two_near_inverse(float x) {
  const auto exponent = static_cast<int>(std::bit_cast<std::uint32_t>(x) >> 23);  // biased
  const int scale_exponent = std::max(254 - exponent, 1);  // 2^(127 - e), kept a normal float
  return std::bit_cast<float>(static_cast<std::uint32_t>(scale_exponent) << 23);
}

}  // namespace

Surface surface(SphereView spheres, const Ray& ray, const Hit& hit) {
  const Vec3 p = ray.at(hit.t);
  if (!hit.found() || hit.id >= spheres.count) return {p, {0.0f, 0.0f, 0.0f}, false};
  const Vec3 center{spheres.cx[hit.id], spheres.cy[hit.id], spheres.cz[hit.id]};
  const float radius = spheres.radius[hit.id];
  // The normal from the centre, not (p - centre) / radius: p is off the sphere by t's rounding,
  // and normalising keeps the normal unit length whatever that error. The point is then put
  // back on the sphere along it, so secondary rays start from the surface itself.
  // A hit at the very centre (radius below float's resolution) has no direction from it: face
  // the ray instead, so the normal is still unit length.
  // The offset is scaled near unit length before it is normalised: the squares of a tiny one
  // (a sphere of radius 1e-22) fall into float's denormals, whose few bits would make the
  // normal's length wrong by percents.
  const Vec3 from_center = p - center;
  const float largest =
      std::max({std::fabs(from_center.x), std::fabs(from_center.y), std::fabs(from_center.z)});
  const bool has_direction = isfinite(from_center) && largest > 0.0f;
  const Vec3 normal = has_direction ? normalize(from_center * power_of_two_near_inverse(largest))
                                    : -normalize(ray.dir);
  return {center + radius * normal, normal, dot(ray.dir, normal) < 0.0f,
          surface_error(center, radius)};
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

}  // namespace sphray
