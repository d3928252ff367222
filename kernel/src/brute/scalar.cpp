// The scalar reference: the kernel's contract in plain C++, one sphere at a time, written to be
// obviously right rather than fast. Tests compare every instruction set against it.
#include <algorithm>
#include <cmath>
#include <optional>

#include "brute/validity.hpp"
#include "bvh/scalar_walk.hpp"
#include "dispatch/entry_table.hpp"
#include "sphray/query.hpp"

namespace sphray::detail {
bool valid_ray(const Ray& ray) {
  const float a = dot(ray.dir, ray.dir);
  return isfinite(ray.origin) && isfinite(ray.dir) && ray.tmin < ray.tmax && a >= 0x1p-126f &&
         std::isfinite(a);
}
}  // namespace sphray::detail

namespace sphray::scalar {
namespace {

using detail::valid_ray;
using detail::valid_sphere;

// The ray parameter at which ray enters the sphere, or leaves it if it starts inside, when that
// lies in (tmin, tmax). The same operations in the same order as SphereLanes::roots
// (brute/sphere_lanes.hpp), which explains the method: every instruction set returns these bits.
std::optional<float> sphere_hit(Vec3 center, float radius, const Ray& ray, float tmax) {
  if (!valid_sphere(center, radius)) return std::nullopt;
  const Vec3 d = ray.dir;
  const Vec3 g = center - ray.origin;
  const float a = d.x * d.x + d.y * d.y + d.z * d.z;
  const float inv_a = 1.0f / a;
  const float b = g.x * d.x + (g.y * d.y + g.z * d.z);
  const float k = b * inv_a;
  const Vec3 v{k * d.x - g.x, k * d.y - g.y, k * d.z - g.z};  // centre to the closest point
  const float disc = radius * radius - (v.x * v.x + (v.y * v.y + v.z * v.z));
  if (!(disc >= 0.0f)) return std::nullopt;
  const float c = k * b - disc;  // |g|^2 - r^2, consistent with disc
  const float q = b + std::copysign(std::sqrt(a * disc), b);
  const float t0 = c / q;
  const float t1 = q * inv_a;
  // t0 is NaN only for 0/0 (origin on the sphere, tangent); both roots are then t1.
  const float near = t0 < t1 ? t0 : t1;
  const float far = t0 > t1 ? t0 : t1;
  const float t = near > ray.tmin ? near : far;
  if (t > ray.tmin && t < tmax) return t;
  return std::nullopt;
}

Vec3 center_of(const SphereView& v, std::size_t i) {
  return {v.cx[i], v.cy[i], v.cz[i]};
}

std::size_t id_count(const SphereView& v) {
  return std::min<std::size_t>(v.count, kNoHit);
}

}  // namespace

Hit intersect(SphereView spheres, const Ray& ray) {
  Hit best{ray.tmax, kNoHit};
  if (!valid_ray(ray)) return best;
  for (std::size_t i = 0; i < id_count(spheres); ++i) {
    // Strictly closer only: on equal t the lower id stays.
    if (auto t = sphere_hit(center_of(spheres, i), spheres.radius[i], ray, best.t))
      best = {*t, static_cast<std::uint32_t>(i)};
  }
  return best;
}

bool occluded(SphereView spheres, const Ray& ray) {
  if (!valid_ray(ray)) return false;
  for (std::size_t i = 0; i < id_count(spheres); ++i)
    if (sphere_hit(center_of(spheres, i), spheres.radius[i], ray, ray.tmax)) return true;
  return false;
}

}  // namespace sphray::scalar

namespace sphray::detail {
namespace {
void scalar_stream(SphereView spheres, const Ray* rays, Hit* hits, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    hits[i] = scalar::intersect(spheres, rays[i]);
}
}  // namespace

constinit const EntryTable kScalarEntries = {Isa::scalar,
                                             1,
                                             &scalar::intersect,
                                             &scalar::occluded,
                                             &scalar_stream,
                                             kScalarBvhWidth,
                                             &scalar_bvh_intersect,
                                             &scalar_bvh_occluded,
                                             &scalar_bvh_intersect_stream};
}  // namespace sphray::detail
