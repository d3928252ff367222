// The public point queries: each forwards to the kernel chosen at run time (by the view's size
// for brute force, the tree's own for a tree) and turns its {distance, id} into the answer.
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
Nearest nearest_result(SphereView spheres, std::size_t slot, Vec3 point, float max_distance,
                       Hit best) {
  if (!best.found() || !(best.t <= max_distance)) return {kNoHit, max_distance, point};
  const Vec3 c{spheres.cx[slot], spheres.cy[slot], spheres.cz[slot]};
  const float r = spheres.radius[slot];
  const Vec3 from = point - c;
  const float largest = std::max({std::fabs(from.x), std::fabs(from.y), std::fabs(from.z)});
  const Vec3 n = largest > 0.0f ? normalize(from / largest) : Vec3{1.0f, 0.0f, 0.0f};
  return {best.id, best.t, c + r * n};
}

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

}  // namespace

Nearest nearest(SphereView spheres, Vec3 point, float max_distance) {
  const Hit best = detail::entries_for_size(spheres.count).nearest(spheres, point, max_distance);
  return detail::nearest_result(spheres, best.id, point, max_distance, best);
}

bool inside(SphereView spheres, Vec3 point) {
  return collect({}, true, [&](detail::IdCollector& ids) {
           detail::entries_for_size(spheres.count).overlapping(spheres, point, 0.0f, ids);
         }) > 0;
}

std::size_t overlapping(SphereView spheres, Vec3 centre, float radius,
                        std::span<std::uint32_t> out) {
  return collect(out, false, [&](detail::IdCollector& ids) {
    detail::entries_for_size(spheres.count).overlapping(spheres, centre, radius, ids);
  });
}

Nearest nearest(const SphereBVH& bvh, Vec3 point, float max_distance) {
  using A = detail::BvhAccess;
  const detail::BvhData& data = A::data(bvh);
  std::size_t slot = 0;
  const Hit best = A::entries(bvh).bvh_nearest(data, point, max_distance, &slot);
  return detail::nearest_result(data.spheres, slot, point, max_distance, best);
}

bool inside(const SphereBVH& bvh, Vec3 point) {
  using A = detail::BvhAccess;
  return collect({}, true, [&](detail::IdCollector& ids) {
           A::entries(bvh).bvh_overlapping(A::data(bvh), point, 0.0f, ids);
         }) > 0;
}

std::size_t overlapping(const SphereBVH& bvh, Vec3 centre, float radius,
                        std::span<std::uint32_t> out) {
  using A = detail::BvhAccess;
  return collect(out, false, [&](detail::IdCollector& ids) {
    A::entries(bvh).bvh_overlapping(A::data(bvh), centre, radius, ids);
  });
}

void overlapping_pairs(const SphereBVH& bvh, std::vector<IdPair>& out, std::size_t part,
                       std::size_t parts) {
  if (!(part < parts))
    throw std::invalid_argument("sphray::overlapping_pairs: expected part < parts");
  using A = detail::BvhAccess;
  A::entries(bvh).bvh_overlapping_pairs(A::data(bvh), part, parts, out);
}

void nearest(SphereView spheres, std::span<const Vec3> points, std::span<Nearest> out,
             float max_distance) {
  check_batch(points.size(), out.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    out[i] = nearest(spheres, points[i], max_distance);
}

void nearest(const SphereBVH& bvh, std::span<const Vec3> points, std::span<Nearest> out,
             float max_distance) {
  check_batch(points.size(), out.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    out[i] = nearest(bvh, points[i], max_distance);
}

void inside(SphereView spheres, std::span<const Vec3> points, std::span<bool> out) {
  check_batch(points.size(), out.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    out[i] = inside(spheres, points[i]);
}

void inside(const SphereBVH& bvh, std::span<const Vec3> points, std::span<bool> out) {
  check_batch(points.size(), out.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    out[i] = inside(bvh, points[i]);
}

}  // namespace sphray
