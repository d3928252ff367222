// The scalar reference: the kernel's contract in plain C++, one sphere at a time, written to be
// obviously right rather than fast. Tests compare every instruction set against it.
#include <algorithm>
#include <cmath>
#include <limits>
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
namespace {
template <Scalar S>
bool valid_line(const BasicRay<S>& ray) {
  const S a = dot(ray.dir, ray.dir);
  return isfinite(ray.origin) && isfinite(ray.dir) && ray.tmin < ray.tmax &&
         a >= std::numeric_limits<S>::min() && std::isfinite(a) && ray.mask != 0;
}
}  // namespace

bool valid_ray(const Ray& ray) {
  return valid_line(ray);
}
bool valid_ray(const Rayd& ray) {
  return valid_line(ray);
}
}  // namespace sphray::detail

namespace sphray::scalar {
namespace {

using detail::valid_ray;
using detail::valid_sphere;

// The sphere's two roots along ray, near <= far, if the line meets it. The same operations in
// the same order as SphereLanes::near_far (brute/sphere_lanes.hpp), which explains the method:
// every instruction set returns these bits, in float and in double.
template <Scalar S>
struct Roots {
  S near, far;
};
template <Scalar S>
std::optional<Roots<S>> sphere_roots(BasicVec3<S> center, S radius, const BasicRay<S>& ray) {
  if (!valid_sphere(center, radius)) return std::nullopt;
  const BasicVec3<S> d = ray.dir;
  const BasicVec3<S> g = center - ray.origin;
  const S a = d.x * d.x + d.y * d.y + d.z * d.z;
  const S inv_a = S(1) / a;
  const S b = g.x * d.x + (g.y * d.y + g.z * d.z);
  const S k = b * inv_a;
  const BasicVec3<S> v{k * d.x - g.x, k * d.y - g.y, k * d.z - g.z};  // centre to closest point
  const S disc = radius * radius - (v.x * v.x + (v.y * v.y + v.z * v.z));
  if (!(disc >= S(0))) return std::nullopt;
  const S c = k * b - disc;  // |g|^2 - r^2, consistent with disc
  const S q = b + std::copysign(std::sqrt(a) * std::sqrt(disc), b);
  const S t0 = c / q;
  const S t1 = q * inv_a;
  // t0 is NaN only for 0/0 (origin on the sphere, tangent); both roots are then t1.
  return Roots<S>{t0 < t1 ? t0 : t1, t0 > t1 ? t0 : t1};
}

// The ray parameter at which ray enters the sphere, or leaves it if it starts inside, when that
// lies in (tmin, tmax).
template <Scalar S>
std::optional<S> sphere_hit(BasicVec3<S> center, S radius, const BasicRay<S>& ray, S tmax) {
  const auto roots = sphere_roots(center, radius, ray);
  if (!roots) return std::nullopt;
  const S t = roots->near > ray.tmin ? roots->near : roots->far;
  if (t > ray.tmin && t < tmax) return t;
  return std::nullopt;
}

// Both crossings of sphere id that lie in (tmin, tmax), into list.
template <Scalar S>
void add_crossings(BasicVec3<S> center, S radius, std::uint32_t id, const BasicRay<S>& ray,
                   detail::SPHRAY_ISA_NAMESPACE::BasicHitList<S>& list) {
  const auto roots = sphere_roots(center, radius, ray);
  if (!roots) return;
  const auto inside = [&](S t) { return t > ray.tmin && t < ray.tmax; };
  if (inside(roots->near)) list.add(roots->near, id, false);
  if (inside(roots->far)) list.add(roots->far, id, true);
}

// Sphere i's radius, or 0 (never hit) if the ray cannot see it: the masks share no bit. The
// kernels hide a sphere the same way (SphereLanes::load_seen).
template <Scalar S>
S seen_radius(const BasicSphereView<S>& v, std::size_t i, const BasicRay<S>& ray) {
  return v.mask == nullptr || (v.mask[i] & ray.mask) != 0 ? v.radius[i] : S(0);
}

template <Scalar S>
BasicVec3<S> center_of(const BasicSphereView<S>& v, std::size_t i) {
  return {v.cx[i], v.cy[i], v.cz[i]};
}

template <Scalar S>
std::size_t id_count(const BasicSphereView<S>& v) {
  return std::min<std::size_t>(v.count, kNoHit);
}

template <Scalar S>
BasicHit<S> closest(const BasicSphereView<S>& spheres, const BasicRay<S>& ray) {
  BasicHit<S> best{ray.tmax, kNoHit};
  if (!detail::valid_ray(ray)) return best;
  for (std::size_t i = 0; i < id_count(spheres); ++i) {
    // Strictly closer only: on equal t the lower id stays.
    if (auto t = sphere_hit(center_of(spheres, i), seen_radius(spheres, i, ray), ray, best.t))
      best = {*t, static_cast<std::uint32_t>(i)};
  }
  return best;
}

template <Scalar S>
bool any(const BasicSphereView<S>& spheres, const BasicRay<S>& ray) {
  if (!detail::valid_ray(ray)) return false;
  for (std::size_t i = 0; i < id_count(spheres); ++i)
    if (sphere_hit(center_of(spheres, i), seen_radius(spheres, i, ray), ray, ray.tmax)) return true;
  return false;
}

}  // namespace

Hit intersect(SphereView spheres, const Ray& ray) {
  return closest(spheres, ray);
}
Hitd intersect(SphereViewd spheres, const Rayd& ray) {
  return closest(spheres, ray);
}
bool occluded(SphereView spheres, const Ray& ray) {
  return any(spheres, ray);
}
bool occluded(SphereViewd spheres, const Rayd& ray) {
  return any(spheres, ray);
}

namespace {
template <Scalar S>
std::size_t every_crossing(const BasicSphereView<S>& spheres, const BasicRay<S>& ray,
                           std::span<BasicHit<S>> out, std::span<bool> exits) {
  if (!exits.empty() && exits.size() != out.size())
    throw std::length_error("sphray::intersect_all: hits and exits differ in size");
  detail::SPHRAY_ISA_NAMESPACE::BasicHitList<S> list(
      out.data(), exits.empty() ? nullptr : exits.data(), out.size());
  if (!valid_ray(ray)) return 0;
  for (std::size_t i = 0; i < id_count(spheres); ++i)
    add_crossings(center_of(spheres, i), seen_radius(spheres, i, ray),
                  static_cast<std::uint32_t>(i), ray, list);
  return list.total();
}
}  // namespace

std::size_t intersect_all(SphereView spheres, const Ray& ray, std::span<Hit> out,
                          std::span<bool> exits) {
  return every_crossing(spheres, ray, out, exits);
}
std::size_t intersect_all(SphereViewd spheres, const Rayd& ray, std::span<Hitd> out,
                          std::span<bool> exits) {
  return every_crossing(spheres, ray, out, exits);
}

}  // namespace sphray::scalar

namespace sphray::detail {
namespace {
template <Scalar S>
std::size_t scalar_intersect_all(BasicSphereView<S> spheres, const BasicRay<S>& ray,
                                 BasicHit<S>* hits, bool* exits, std::size_t capacity) {
  return scalar::intersect_all(spheres, ray, std::span(hits, capacity),
                               std::span(exits, exits == nullptr ? 0 : capacity));
}

// Every crossing does not depend on the order spheres are visited in: the tree's slots, each
// with its id, one at a time (padding slots have radius 0 and are never hit).
template <Scalar S>
std::size_t scalar_bvh_intersect_all(const BasicBvhData<S>& bvh, const BasicRay<S>& ray,
                                     BasicHit<S>* hits, bool* exits, std::size_t capacity) {
  SPHRAY_ISA_NAMESPACE::BasicHitList<S> list(hits, exits, capacity);
  if (!valid_ray(ray)) return 0;
  const BasicSphereView<S>& slots = bvh.spheres;
  for (std::size_t i = 0; i < slots.count; ++i)
    scalar::add_crossings({slots.cx[i], slots.cy[i], slots.cz[i]},
                          scalar::seen_radius(slots, i, ray), bvh.ids[i], ray, list);
  return list.total();
}

// The nearest crossings are the first of every crossing: the reference needs no pruning.
template <Scalar S>
std::size_t scalar_bvh_intersect_nearest(const BasicBvhData<S>& bvh, const BasicRay<S>& ray,
                                         BasicHit<S>* hits, bool* exits, std::size_t capacity) {
  return std::min(scalar_bvh_intersect_all(bvh, ray, hits, exits, capacity), capacity);
}

// The streams in float and double.
template <Scalar S>
void scalar_stream(BasicSphereView<S> spheres, const BasicRay<S>* rays, BasicHit<S>* hits,
                   std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    hits[i] = scalar::intersect(spheres, rays[i]);
}

template <Scalar S>
void scalar_occluded_stream(BasicSphereView<S> spheres, const BasicRay<S>* rays, bool* blocked,
                            std::size_t n) {
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
                                             &scalar_stream<float>,
                                             &scalar_arrays,
                                             &scalar_occluded_stream<float>,
                                             &scalar_stream<float>,
                                             &scalar_occluded_stream<float>,
                                             kScalarBvhWidth,
                                             &scalar_bvh_intersect<float>,
                                             &scalar_bvh_occluded<float>,
                                             &scalar_bvh_intersect_stream<float>,
                                             &scalar_bvh_arrays,
                                             &scalar_bvh_occluded_stream<float>,
                                             &scalar_intersect_all<float>,
                                             &scalar_bvh_intersect_all<float>,
                                             &scalar_bvh_intersect_nearest<float>,
                                             &scalar_nearest<float>,
                                             &scalar_overlapping<float>,
                                             &scalar_bvh_nearest<float>,
                                             &scalar_bvh_overlapping<float>,
                                             &scalar_bvh_overlapping_pairs<float>,
                                             &scalar_surfaces,
                                             &scalar_offset_origins,
                                             1,
                                             &scalar::intersect,
                                             &scalar::occluded,
                                             &scalar_stream<double>,
                                             &scalar_occluded_stream<double>,
                                             &scalar_intersect_all<double>,
                                             kScalarBvhWidth,
                                             &scalar_bvh_intersect<double>,
                                             &scalar_bvh_occluded<double>,
                                             &scalar_bvh_intersect_stream<double>,
                                             &scalar_bvh_occluded_stream<double>,
                                             &scalar_bvh_intersect_all<double>,
                                             &scalar_bvh_intersect_nearest<double>,
                                             &scalar_nearest<double>,
                                             &scalar_overlapping<double>,
                                             &scalar_bvh_nearest<double>,
                                             &scalar_bvh_overlapping<double>,
                                             &scalar_bvh_overlapping_pairs<double>};
}  // namespace sphray::detail
