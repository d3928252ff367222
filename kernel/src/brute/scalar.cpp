// The scalar reference: the kernel's contract in plain C++, one sphere at a time, written to be
// obviously right rather than fast. Tests compare every instruction set against it.
#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <stdexcept>

#include "all_hits/hit_list.hpp"
#include "brute/validity.hpp"
#include "bvh/bvh_data.hpp"
#include "bvh/scalar_walk.hpp"
#include "dispatch/entry_table.hpp"
#include "point/point_queries_common.hpp"
#include "sphray/all_hits.hpp"
#include "sphray/query.hpp"

namespace sphray::detail {
bool valid_ray(const Ray& ray) {
  const float a = dot(ray.dir, ray.dir);
  return isfinite(ray.origin) && isfinite(ray.dir) && ray.tmin < ray.tmax && a >= 0x1p-126f &&
         std::isfinite(a) && ray.mask != 0;
}
}  // namespace sphray::detail

namespace sphray::scalar {
namespace {

using detail::valid_ray;
using detail::valid_sphere;

// The sphere's two roots along ray, near <= far, if the line meets it. The same operations in
// the same order as SphereLanes::near_far (brute/sphere_lanes.hpp), which explains the method:
// every instruction set returns these bits.
struct Roots {
  float near, far;
};
std::optional<Roots> sphere_roots(Vec3 center, float radius, const Ray& ray) {
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
  const float q = b + std::copysign(std::sqrt(a) * std::sqrt(disc), b);
  const float t0 = c / q;
  const float t1 = q * inv_a;
  // t0 is NaN only for 0/0 (origin on the sphere, tangent); both roots are then t1.
  return Roots{t0 < t1 ? t0 : t1, t0 > t1 ? t0 : t1};
}

// The ray parameter at which ray enters the sphere, or leaves it if it starts inside, when that
// lies in (tmin, tmax).
std::optional<float> sphere_hit(Vec3 center, float radius, const Ray& ray, float tmax) {
  const auto roots = sphere_roots(center, radius, ray);
  if (!roots) return std::nullopt;
  const float t = roots->near > ray.tmin ? roots->near : roots->far;
  if (t > ray.tmin && t < tmax) return t;
  return std::nullopt;
}

// Both crossings of sphere id that lie in (tmin, tmax), into list.
void add_crossings(Vec3 center, float radius, std::uint32_t id, const Ray& ray,
                   detail::SPHRAY_ISA_NAMESPACE::HitList& list) {
  const auto roots = sphere_roots(center, radius, ray);
  if (!roots) return;
  const auto inside = [&](float t) { return t > ray.tmin && t < ray.tmax; };
  if (inside(roots->near)) list.add(roots->near, id, false);
  if (inside(roots->far)) list.add(roots->far, id, true);
}

// Sphere i's radius, or 0 (never hit) if the ray cannot see it: the masks share no bit. The
// kernels hide a sphere the same way (SphereLanes::load_seen).
float seen_radius(const SphereView& v, std::size_t i, const Ray& ray) {
  return v.mask == nullptr || (v.mask[i] & ray.mask) != 0 ? v.radius[i] : 0.0f;
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
    if (auto t = sphere_hit(center_of(spheres, i), seen_radius(spheres, i, ray), ray, best.t))
      best = {*t, static_cast<std::uint32_t>(i)};
  }
  return best;
}

bool occluded(SphereView spheres, const Ray& ray) {
  if (!valid_ray(ray)) return false;
  for (std::size_t i = 0; i < id_count(spheres); ++i)
    if (sphere_hit(center_of(spheres, i), seen_radius(spheres, i, ray), ray, ray.tmax)) return true;
  return false;
}

std::size_t intersect_all(SphereView spheres, const Ray& ray, std::span<Hit> out,
                          std::span<bool> exits) {
  if (!exits.empty() && exits.size() != out.size())
    throw std::length_error("sphray::intersect_all: hits and exits differ in size");
  detail::SPHRAY_ISA_NAMESPACE::HitList list(out.data(), exits.empty() ? nullptr : exits.data(),
                                             out.size());
  if (!valid_ray(ray)) return 0;
  for (std::size_t i = 0; i < id_count(spheres); ++i)
    add_crossings(center_of(spheres, i), seen_radius(spheres, i, ray),
                  static_cast<std::uint32_t>(i), ray, list);
  return list.total();
}

}  // namespace sphray::scalar

namespace sphray::detail {
namespace {
std::size_t scalar_intersect_all(SphereView spheres, const Ray& ray, Hit* hits, bool* exits,
                                 std::size_t capacity) {
  return scalar::intersect_all(spheres, ray, std::span(hits, capacity),
                               std::span(exits, exits == nullptr ? 0 : capacity));
}

// Every crossing does not depend on the order spheres are visited in: the tree's slots, each
// with its id, one at a time (padding slots have radius 0 and are never hit).
std::size_t scalar_bvh_intersect_all(const BvhData& bvh, const Ray& ray, Hit* hits, bool* exits,
                                     std::size_t capacity) {
  SPHRAY_ISA_NAMESPACE::HitList list(hits, exits, capacity);
  if (!valid_ray(ray)) return 0;
  const SphereView& slots = bvh.spheres;
  for (std::size_t i = 0; i < slots.count; ++i)
    scalar::add_crossings({slots.cx[i], slots.cy[i], slots.cz[i]},
                          scalar::seen_radius(slots, i, ray), bvh.ids[i], ray, list);
  return list.total();
}

// The nearest crossings are the first of every crossing: the reference needs no pruning.
std::size_t scalar_bvh_intersect_nearest(const BvhData& bvh, const Ray& ray, Hit* hits, bool* exits,
                                         std::size_t capacity) {
  return std::min(scalar_bvh_intersect_all(bvh, ray, hits, exits, capacity), capacity);
}

void scalar_stream(SphereView spheres, const Ray* rays, Hit* hits, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    hits[i] = scalar::intersect(spheres, rays[i]);
}

void scalar_occluded_stream(SphereView spheres, const Ray* rays, bool* blocked, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    blocked[i] = scalar::occluded(spheres, rays[i]);
}

void scalar_arrays(SphereView spheres, const RayArrays& rays, const HitArrays& hits) {
  for (std::size_t i = 0; i < rays.count; ++i)
    hits.set(i, scalar::intersect(spheres, rays.at(i)));
}

void scalar_bvh_arrays(const BvhData& bvh, const RayArrays& rays, const HitArrays& hits) {
  for (std::size_t i = 0; i < rays.count; ++i)
    hits.set(i, scalar_bvh_intersect(bvh, rays.at(i)));
}

void scalar_surfaces(SphereView spheres, const RayArrays& rays, const HitArrays& hits,
                     const SurfaceArrays& out) {
  for (std::size_t i = 0; i < rays.count; ++i)
    out.set(i, surface(spheres, rays.at(i), hits.at(i)));
}

void scalar_offset_origins(const SurfaceArrays& surfaces, const VectorArrays& dirs,
                           const VectorOutArrays& origins) {
  for (std::size_t i = 0; i < surfaces.count; ++i)
    origins.set(i, offset_origin(surfaces.at(i), dirs.at(i)));
}
}  // namespace

// One lane: the rays-across streams are the streams.
constinit const EntryTable kScalarEntries = {Isa::scalar,
                                             1,
                                             &scalar::intersect,
                                             &scalar::occluded,
                                             &scalar_stream,
                                             &scalar_arrays,
                                             &scalar_occluded_stream,
                                             &scalar_stream,
                                             &scalar_occluded_stream,
                                             kScalarBvhWidth,
                                             &scalar_bvh_intersect,
                                             &scalar_bvh_occluded,
                                             &scalar_bvh_intersect_stream,
                                             &scalar_bvh_arrays,
                                             &scalar_bvh_occluded_stream,
                                             &scalar_intersect_all,
                                             &scalar_bvh_intersect_all,
                                             &scalar_bvh_intersect_nearest,
                                             &scalar_nearest,
                                             &scalar_overlapping,
                                             &scalar_bvh_nearest,
                                             &scalar_bvh_overlapping,
                                             &scalar_bvh_overlapping_pairs,
                                             &scalar_surfaces,
                                             &scalar_offset_origins};
}  // namespace sphray::detail
