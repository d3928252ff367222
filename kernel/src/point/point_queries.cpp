// The public point queries in float and double: each forwards to the kernel chosen at run time
// (by the view's size for brute force, the tree's own for a tree) and turns its {distance, id}
// into the answer. One body per query for both precisions; the overloads name the entry.
#include "sphray/point_queries.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "bvh/bvh_data.hpp"
#include "dispatch/entry_table.hpp"
#include "point/id_collector.hpp"
#include "point/point_queries_common.hpp"

namespace sphray {

namespace detail {

// The surface point nearest p: along p - c from the centre. The offset is divided by its
// largest component first, as surface() does, so that a tiny one keeps its direction; from
// the centre itself every surface point is as near, and +x is taken.
template <Scalar S>
BasicNearest<S> nearest_result(BasicSphereView<S> spheres, std::size_t slot, BasicVec3<S> point,
                               S max_distance, BasicHit<S> best) {
  if (!best.found() || !(best.t <= max_distance)) return {kNoHit, max_distance, point};
  const BasicVec3<S> c{spheres.cx[slot], spheres.cy[slot], spheres.cz[slot]};
  const S r = spheres.radius[slot];
  const BasicVec3<S> from = point - c;
  const S largest = std::max({std::fabs(from.x), std::fabs(from.y), std::fabs(from.z)});
  const BasicVec3<S> n = largest > S(0) ? normalize(from / largest) : BasicVec3<S>{1, 0, 0};
  return {best.id, best.t, c + r * n};
}

template Nearest nearest_result(SphereView, std::size_t, Vec3, float, Hit);
template Nearestd nearest_result(SphereViewd, std::size_t, Vec3d, double, Hitd);

}  // namespace detail

namespace {

void check_batch(std::size_t points, std::size_t out) {
  if (points != out)
    throw std::length_error("sphray: expected one answer per point (out.size() == points.size())");
}

std::size_t collect(std::span<std::uint32_t> out, bool first_only, auto&& query) {
  detail::IdCollector ids{out.data(), first_only ? 0 : out.size(), first_only};
  query(ids);
  ids.finish();
  return ids.total;
}

// Brute force on a view, in S.
template <Scalar S>
BasicNearest<S> view_nearest(BasicSphereView<S> spheres, BasicVec3<S> point, S max_distance) {
  const auto& k = detail::entries_for_size(spheres.count);
  const BasicHit<S> best =
      detail::in_precision<S>(k.nearest, k.nearest_d)(spheres, point, max_distance);
  return detail::nearest_result(spheres, best.id, point, max_distance, best);
}

template <Scalar S>
std::size_t view_overlapping(BasicSphereView<S> spheres, BasicVec3<S> centre, S radius,
                             std::span<std::uint32_t> out, bool first_only) {
  return collect(out, first_only, [&](detail::IdCollector& ids) {
    const auto& k = detail::entries_for_size(spheres.count);
    detail::in_precision<S>(k.overlapping, k.overlapping_d)(spheres, centre, radius, ids);
  });
}

// Through a tree, in S.
template <Scalar S>
BasicNearest<S> tree_nearest(const BasicSphereBVH<S>& bvh, BasicVec3<S> point, S max_distance) {
  using A = detail::BvhAccess;
  const auto& data = A::data(bvh);
  const auto& k = A::entries(bvh);
  std::size_t slot = 0;
  const BasicHit<S> best =
      detail::in_precision<S>(k.bvh_nearest, k.bvh_nearest_d)(data, point, max_distance, &slot);
  return detail::nearest_result(data.spheres, slot, point, max_distance, best);
}

template <Scalar S>
std::size_t tree_overlapping(const BasicSphereBVH<S>& bvh, BasicVec3<S> centre, S radius,
                             std::span<std::uint32_t> out, bool first_only) {
  using A = detail::BvhAccess;
  return collect(out, first_only, [&](detail::IdCollector& ids) {
    const auto& k = A::entries(bvh);
    detail::in_precision<S>(k.bvh_overlapping, k.bvh_overlapping_d)(A::data(bvh), centre, radius,
                                                                    ids);
  });
}

template <Scalar S>
void tree_overlapping_pairs(const BasicSphereBVH<S>& bvh, std::vector<IdPair>& out,
                            std::size_t part, std::size_t parts) {
  if (!(part < parts))
    throw std::invalid_argument("sphray::overlapping_pairs: expected part < parts");
  using A = detail::BvhAccess;
  const auto& k = A::entries(bvh);
  detail::in_precision<S>(k.bvh_overlapping_pairs, k.bvh_overlapping_pairs_d)(A::data(bvh), part,
                                                                              parts, out);
}

// out[i] = query(points[i]) for every point.
template <class Point, class Answer, class Query>
void each_point(std::span<const Point> points, std::span<Answer> out, Query&& query) {
  check_batch(points.size(), out.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    out[i] = query(points[i]);
}

}  // namespace

Nearest nearest(SphereView spheres, Vec3 point, float max_distance) {
  return view_nearest(spheres, point, max_distance);
}
Nearestd nearest(SphereViewd spheres, Vec3d point, double max_distance) {
  return view_nearest(spheres, point, max_distance);
}

bool inside(SphereView spheres, Vec3 point) {
  return view_overlapping(spheres, point, 0.0f, {}, true) > 0;
}
bool inside(SphereViewd spheres, Vec3d point) {
  return view_overlapping(spheres, point, 0.0, {}, true) > 0;
}

std::size_t overlapping(SphereView spheres, Vec3 centre, float radius,
                        std::span<std::uint32_t> out) {
  return view_overlapping(spheres, centre, radius, out, false);
}
std::size_t overlapping(SphereViewd spheres, Vec3d centre, double radius,
                        std::span<std::uint32_t> out) {
  return view_overlapping(spheres, centre, radius, out, false);
}

Nearest nearest(const SphereBVH& bvh, Vec3 point, float max_distance) {
  return tree_nearest(bvh, point, max_distance);
}
Nearestd nearest(const SphereBVHd& bvh, Vec3d point, double max_distance) {
  return tree_nearest(bvh, point, max_distance);
}

bool inside(const SphereBVH& bvh, Vec3 point) {
  return tree_overlapping(bvh, point, 0.0f, {}, true) > 0;
}
bool inside(const SphereBVHd& bvh, Vec3d point) {
  return tree_overlapping(bvh, point, 0.0, {}, true) > 0;
}

std::size_t overlapping(const SphereBVH& bvh, Vec3 centre, float radius,
                        std::span<std::uint32_t> out) {
  return tree_overlapping(bvh, centre, radius, out, false);
}
std::size_t overlapping(const SphereBVHd& bvh, Vec3d centre, double radius,
                        std::span<std::uint32_t> out) {
  return tree_overlapping(bvh, centre, radius, out, false);
}

void overlapping_pairs(const SphereBVH& bvh, std::vector<IdPair>& out, std::size_t part,
                       std::size_t parts) {
  tree_overlapping_pairs(bvh, out, part, parts);
}
void overlapping_pairs(const SphereBVHd& bvh, std::vector<IdPair>& out, std::size_t part,
                       std::size_t parts) {
  tree_overlapping_pairs(bvh, out, part, parts);
}

void nearest(SphereView spheres, std::span<const Vec3> points, std::span<Nearest> out,
             float max_distance) {
  each_point(points, out, [&](Vec3 p) { return nearest(spheres, p, max_distance); });
}
void nearest(SphereViewd spheres, std::span<const Vec3d> points, std::span<Nearestd> out,
             double max_distance) {
  each_point(points, out, [&](Vec3d p) { return nearest(spheres, p, max_distance); });
}
void nearest(const SphereBVH& bvh, std::span<const Vec3> points, std::span<Nearest> out,
             float max_distance) {
  each_point(points, out, [&](Vec3 p) { return nearest(bvh, p, max_distance); });
}
void nearest(const SphereBVHd& bvh, std::span<const Vec3d> points, std::span<Nearestd> out,
             double max_distance) {
  each_point(points, out, [&](Vec3d p) { return nearest(bvh, p, max_distance); });
}

void inside(SphereView spheres, std::span<const Vec3> points, std::span<bool> out) {
  each_point(points, out, [&](Vec3 p) { return inside(spheres, p); });
}
void inside(SphereViewd spheres, std::span<const Vec3d> points, std::span<bool> out) {
  each_point(points, out, [&](Vec3d p) { return inside(spheres, p); });
}
void inside(const SphereBVH& bvh, std::span<const Vec3> points, std::span<bool> out) {
  each_point(points, out, [&](Vec3 p) { return inside(bvh, p); });
}
void inside(const SphereBVHd& bvh, std::span<const Vec3d> points, std::span<bool> out) {
  each_point(points, out, [&](Vec3d p) { return inside(bvh, p); });
}

}  // namespace sphray
