// Beyond the closest hit: every crossing of a ray with the spheres' surfaces, for transparency,
// densities along a line of sight, counting layers, or telling inside from outside.
//
// Contract (all instruction sets, the scalar reference and the tree alike, bit for bit):
// - A sphere's crossings are its two roots along the ray, near <= far, the same floats the
//   closest-hit query computes (query.hpp); each counts where it lies in (tmin, tmax). The near
//   root is an entry, the far root an exit: a ray starting inside a sphere has only its exit, a
//   tangent ray an entry and an exit at the same t.
// - The crossings are ordered by t, then by sphere id, then entry before exit. The first one is
//   the closest hit: intersect(spheres, ray) returns its t and id whenever there is one.
// - intersect_all fills out with the first out.size() crossings in that order and returns how
//   many there are in all (more than out.size() when out is too small; out's other elements are
//   left as they were). count_hits returns that number alone.
// - intersect_nearest fills out with the same first out.size() crossings, bit for bit, and
//   returns how many it wrote (at most out.size()), without the total: through a tree it stops
//   at the out.size()-th crossing found so far, as the closest hit stops at the first, instead
//   of reading every leaf along the ray.
// - Rays and spheres the closest-hit contract never lets hit (NaN, infinite, degenerate) have no
//   crossings. The queries never allocate; they throw only std::length_error, on spans whose
//   sizes do not match (below).
#pragma once

#include <cstddef>
#include <span>

#include "sphray/api.h"
#include "sphray/bvh.hpp"
#include "sphray/ray.hpp"
#include "sphray/spheres.hpp"

namespace sphray {

/// The first out.size() crossings of ray with the spheres, sorted; returns their total number.
SPHRAY_API std::size_t intersect_all(SphereView spheres, const Ray& ray, std::span<Hit> out);
/// As above, and exits[i] tells whether out[i] is where the ray leaves its sphere. exits is
/// empty (not wanted) or out.size() long.
SPHRAY_API std::size_t intersect_all(SphereView spheres, const Ray& ray, std::span<Hit> out,
                                     std::span<bool> exits);
/// The number of crossings of ray with the spheres in (tmin, tmax).
SPHRAY_API std::size_t count_hits(SphereView spheres, const Ray& ray);

/// The same queries through a tree: the same results as on the spheres it was built (or last
/// refitted) from.
SPHRAY_API std::size_t intersect_all(const SphereBVH& bvh, const Ray& ray, std::span<Hit> out);
SPHRAY_API std::size_t intersect_all(const SphereBVH& bvh, const Ray& ray, std::span<Hit> out,
                                     std::span<bool> exits);
SPHRAY_API std::size_t count_hits(const SphereBVH& bvh, const Ray& ray);

/// Batch forms, one answer per ray: counts[i] = count_hits(spheres, rays[i]); and the first
/// per_ray crossings of rays[i] in out[i * per_ray ...], their total in counts[i]. Throw
/// std::length_error unless counts.size() == rays.size() and out.size() == rays.size() * per_ray.
SPHRAY_API void count_hits(SphereView spheres, std::span<const Ray> rays,
                           std::span<std::size_t> counts);
SPHRAY_API void count_hits(const SphereBVH& bvh, std::span<const Ray> rays,
                           std::span<std::size_t> counts);
SPHRAY_API void intersect_all(SphereView spheres, std::span<const Ray> rays, std::span<Hit> out,
                              std::size_t per_ray, std::span<std::size_t> counts);
SPHRAY_API void intersect_all(const SphereBVH& bvh, std::span<const Ray> rays, std::span<Hit> out,
                              std::size_t per_ray, std::span<std::size_t> counts);

/// The nearest out.size() crossings alone: intersect_all's first out.size() (and exits),
/// without the total; returns how many were written. Through a tree the walk stops at the
/// out.size()-th crossing found so far (k-buffers, the first layers of transparency).
SPHRAY_API std::size_t intersect_nearest(SphereView spheres, const Ray& ray, std::span<Hit> out);
SPHRAY_API std::size_t intersect_nearest(SphereView spheres, const Ray& ray, std::span<Hit> out,
                                         std::span<bool> exits);
SPHRAY_API std::size_t intersect_nearest(const SphereBVH& bvh, const Ray& ray, std::span<Hit> out);
SPHRAY_API std::size_t intersect_nearest(const SphereBVH& bvh, const Ray& ray, std::span<Hit> out,
                                         std::span<bool> exits);
/// Batch forms: the nearest per_ray crossings of rays[i] in out[i * per_ray ...], how many in
/// counts[i]. Throw std::length_error as intersect_all's.
SPHRAY_API void intersect_nearest(SphereView spheres, std::span<const Ray> rays, std::span<Hit> out,
                                  std::size_t per_ray, std::span<std::size_t> counts);
SPHRAY_API void intersect_nearest(const SphereBVH& bvh, std::span<const Ray> rays,
                                  std::span<Hit> out, std::size_t per_ray,
                                  std::span<std::size_t> counts);

/// Every crossing in double (docs/double.md), by brute force and through a SphereBVHd: the same
/// contract and order as in float.
SPHRAY_API std::size_t intersect_all(SphereViewd spheres, const Rayd& ray, std::span<Hitd> out,
                                     std::span<bool> exits = {});
SPHRAY_API std::size_t count_hits(SphereViewd spheres, const Rayd& ray);
SPHRAY_API std::size_t intersect_nearest(SphereViewd spheres, const Rayd& ray, std::span<Hitd> out,
                                         std::span<bool> exits = {});
SPHRAY_API std::size_t intersect_all(const SphereBVHd& bvh, const Rayd& ray, std::span<Hitd> out,
                                     std::span<bool> exits = {});
SPHRAY_API std::size_t count_hits(const SphereBVHd& bvh, const Rayd& ray);
SPHRAY_API std::size_t intersect_nearest(const SphereBVHd& bvh, const Rayd& ray,
                                         std::span<Hitd> out, std::span<bool> exits = {});
/// Their batch forms in double, as float's above.
SPHRAY_API void count_hits(SphereViewd spheres, std::span<const Rayd> rays,
                           std::span<std::size_t> counts);
SPHRAY_API void count_hits(const SphereBVHd& bvh, std::span<const Rayd> rays,
                           std::span<std::size_t> counts);
SPHRAY_API void intersect_all(SphereViewd spheres, std::span<const Rayd> rays, std::span<Hitd> out,
                              std::size_t per_ray, std::span<std::size_t> counts);
SPHRAY_API void intersect_all(const SphereBVHd& bvh, std::span<const Rayd> rays,
                              std::span<Hitd> out, std::size_t per_ray,
                              std::span<std::size_t> counts);
SPHRAY_API void intersect_nearest(SphereViewd spheres, std::span<const Rayd> rays,
                                  std::span<Hitd> out, std::size_t per_ray,
                                  std::span<std::size_t> counts);
SPHRAY_API void intersect_nearest(const SphereBVHd& bvh, std::span<const Rayd> rays,
                                  std::span<Hitd> out, std::size_t per_ray,
                                  std::span<std::size_t> counts);

namespace scalar {
/// The reference implementation, one sphere at a time.
SPHRAY_API std::size_t intersect_all(SphereView spheres, const Ray& ray, std::span<Hit> out,
                                     std::span<bool> exits);
SPHRAY_API std::size_t intersect_all(SphereViewd spheres, const Rayd& ray, std::span<Hitd> out,
                                     std::span<bool> exits);
}  // namespace scalar

}  // namespace sphray
