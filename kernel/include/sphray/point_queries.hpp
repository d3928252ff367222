// Questions about points rather than rays: the sphere nearest a point, whether a point is
// inside any sphere (occupancy), and which spheres a query ball overlaps (collision
// candidates). For particle simulations, signed-distance lookups and picking.
//
// Contract (all instruction sets, the scalar reference and the tree alike, bit for bit):
// - The signed distance from a point p to sphere i is d_i = |p - c_i| - r_i (negative inside),
//   in float, by the same operations everywhere (docs/queries.md).
// - nearest: the sphere of smallest d_i with d_i <= max_distance, ties to the lower id. Inside
//   overlapping spheres that is the one p is deepest in: min_i d_i is the union's signed
//   distance, the usual convention for sets of spheres. A miss has id kNoHit, distance
//   max_distance and point p.
// - inside: whether any d_i < 0 (the open balls).
// - overlapping: the ids of the spheres with d_i < radius, ascending: the first out.size() of
//   them into out; returns how many there are in all. Touching is not overlapping.
// - overlapping_pairs: every pair i < j of spheres with j among overlapping(c_i, r_i) (the lower
//   id's sphere as the ball), each pair once.
// - Spheres the ray queries never hit (a NaN or infinite centre, a radius outside
//   [2^-63, 2^64): query.hpp) are never found. A
//   NaN or infinite point, a NaN max_distance, or a radius that is negative or NaN gives the
//   empty answer (a miss, false, 0). No allocation, no locks, no global state.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "sphray/api.h"
#include "sphray/bvh.hpp"
#include "sphray/ray.hpp"
#include "sphray/spheres.hpp"

namespace sphray {

template <Scalar S>
struct BasicNearest {
  std::uint32_t id = kNoHit;
  S distance = std::numeric_limits<S>::infinity();  // signed: negative inside
  BasicVec3<S> point{0, 0, 0};                      // the closest point of that sphere's surface
  bool found() const { return id != kNoHit; }
};
using Nearest = BasicNearest<float>;
using Nearestd = BasicNearest<double>;

/// No maximum distance, in either precision (float's infinity is double's).
inline constexpr float kAnyDistance = std::numeric_limits<float>::infinity();

/// The sphere nearest point whose signed distance is at most max_distance.
SPHRAY_API Nearest nearest(SphereView spheres, Vec3 point, float max_distance = kAnyDistance);
/// Whether point lies inside any sphere.
SPHRAY_API bool inside(SphereView spheres, Vec3 point);
/// The spheres overlapping the ball (centre, radius), ascending by id: the first out.size()
/// into out; returns their total number.
SPHRAY_API std::size_t overlapping(SphereView spheres, Vec3 centre, float radius,
                                   std::span<std::uint32_t> out);

/// The same through a tree, walked by distance: the same results as on the spheres it was
/// built (or last refitted) from.
SPHRAY_API Nearest nearest(const SphereBVH& bvh, Vec3 point, float max_distance = kAnyDistance);
SPHRAY_API bool inside(const SphereBVH& bvh, Vec3 point);
SPHRAY_API std::size_t overlapping(const SphereBVH& bvh, Vec3 centre, float radius,
                                   std::span<std::uint32_t> out);

/// Two overlapping spheres' ids, first < second.
struct IdPair {
  std::uint32_t first, second;
  friend bool operator==(IdPair, IdPair) = default;
};

/// The pairs of the tree's spheres that overlap (a simulation's broad phase), appended to out
/// in no particular order: exactly the pairs {i, j}, i < j, with j among overlapping(bvh, c_i,
/// r_i), each once. The work comes in `parts` shares of the tree: part k of them finds its
/// share, and parts 0 to parts - 1 together find every pair once, so that callers may run the
/// shares on threads of their own (each into its own out) and stop between them. Throws
/// std::invalid_argument unless part < parts.
SPHRAY_API void overlapping_pairs(const SphereBVH& bvh, std::vector<IdPair>& out,
                                  std::size_t part = 0, std::size_t parts = 1);

/// Batch forms, one answer per point: out[i] = nearest(spheres, points[i], max_distance) and
/// inside(spheres, points[i]). Throw std::length_error unless out.size() == points.size().
SPHRAY_API void nearest(SphereView spheres, std::span<const Vec3> points, std::span<Nearest> out,
                        float max_distance = kAnyDistance);
SPHRAY_API void nearest(const SphereBVH& bvh, std::span<const Vec3> points, std::span<Nearest> out,
                        float max_distance = kAnyDistance);
SPHRAY_API void inside(SphereView spheres, std::span<const Vec3> points, std::span<bool> out);
SPHRAY_API void inside(const SphereBVH& bvh, std::span<const Vec3> points, std::span<bool> out);

/// The point queries in double (docs/double.md): the same contract with double's distances and
/// double's valid spheres, on views and on double trees, one point at a time and in batches.
SPHRAY_API Nearestd nearest(SphereViewd spheres, Vec3d point, double max_distance = kAnyDistance);
SPHRAY_API bool inside(SphereViewd spheres, Vec3d point);
SPHRAY_API std::size_t overlapping(SphereViewd spheres, Vec3d centre, double radius,
                                   std::span<std::uint32_t> out);
SPHRAY_API Nearestd nearest(const SphereBVHd& bvh, Vec3d point, double max_distance = kAnyDistance);
SPHRAY_API bool inside(const SphereBVHd& bvh, Vec3d point);
SPHRAY_API std::size_t overlapping(const SphereBVHd& bvh, Vec3d centre, double radius,
                                   std::span<std::uint32_t> out);
SPHRAY_API void nearest(SphereViewd spheres, std::span<const Vec3d> points, std::span<Nearestd> out,
                        double max_distance = kAnyDistance);
SPHRAY_API void nearest(const SphereBVHd& bvh, std::span<const Vec3d> points,
                        std::span<Nearestd> out, double max_distance = kAnyDistance);
SPHRAY_API void inside(SphereViewd spheres, std::span<const Vec3d> points, std::span<bool> out);
SPHRAY_API void inside(const SphereBVHd& bvh, std::span<const Vec3d> points, std::span<bool> out);
SPHRAY_API void overlapping_pairs(const SphereBVHd& bvh, std::vector<IdPair>& out,
                                  std::size_t part = 0, std::size_t parts = 1);

namespace scalar {
/// The reference implementations, one sphere at a time.
SPHRAY_API Nearest nearest(SphereView spheres, Vec3 point, float max_distance = kAnyDistance);
SPHRAY_API std::size_t overlapping(SphereView spheres, Vec3 centre, float radius,
                                   std::span<std::uint32_t> out);
SPHRAY_API Nearestd nearest(SphereViewd spheres, Vec3d point, double max_distance = kAnyDistance);
SPHRAY_API std::size_t overlapping(SphereViewd spheres, Vec3d centre, double radius,
                                   std::span<std::uint32_t> out);
}  // namespace scalar

}  // namespace sphray
