// The point queries' scalar reference, one sphere at a time, and the scalar kernel's entries
// for them. The signed distance is point_lanes.hpp's, operation for operation.
#include <algorithm>
#include <cmath>
#include <span>

#include "brute/validity.hpp"
#include "bvh/bvh_data.hpp"
#include "dispatch/entry_table.hpp"
#include "point/id_collector.hpp"
#include "point/point_queries_common.hpp"
#include "sphray/point_queries.hpp"

namespace sphray {
namespace {

using detail::valid_sphere;

bool finite(Vec3 p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

float distance(Vec3 p, Vec3 c) {
  const Vec3 g = c - p;
  return std::sqrt(g.x * g.x + (g.y * g.y + g.z * g.z));
}

float signed_distance(Vec3 p, Vec3 c, float r) {
  return distance(p, c) - r;
}

// Visits slot i of n with its id: a view's own (ids = nullptr) or a tree's leaf slots.
// Invalid spheres are passed over but still counted in the slot index the visitor keeps.
template <class Visit>
void each_sphere(SphereView v, const std::uint32_t* ids, Visit&& visit) {
  const std::size_t n = ids != nullptr ? v.count : std::min<std::size_t>(v.count, kNoHit);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 c{v.cx[i], v.cy[i], v.cz[i]};
    const bool valid = valid_sphere(c, v.radius[i]);
    if (visit(valid, c, v.radius[i], ids != nullptr ? ids[i] : static_cast<std::uint32_t>(i)))
      return;
  }
}

Hit nearest_in(SphereView v, const std::uint32_t* ids, Vec3 point, std::size_t* slot) {
  Hit best{INFINITY, kNoHit};
  if (!finite(point)) return best;
  std::size_t i = 0;
  each_sphere(v, ids, [&](bool valid, Vec3 c, float r, std::uint32_t id) {
    const std::size_t at = i++;
    if (!valid) return false;
    const float d = signed_distance(point, c, r);
    if (d < best.t || (d == best.t && best.id != kNoHit && id < best.id)) {
      best = {d, id};
      if (slot != nullptr) *slot = at;
    }
    return false;
  });
  return best.t < INFINITY ? best : Hit{INFINITY, kNoHit};
}

std::size_t overlapping_in(SphereView v, const std::uint32_t* ids, Vec3 centre, float radius,
                           detail::IdCollector& out) {
  if (!finite(centre) || !(radius >= 0.0f)) return 0;
  each_sphere(v, ids, [&](bool valid, Vec3 c, float r, std::uint32_t id) {
    return valid && signed_distance(centre, c, r) < radius && out.add(id);
  });
  return out.total;
}

}  // namespace

namespace scalar {

Nearest nearest(SphereView spheres, Vec3 point, float max_distance) {
  const Hit best = nearest_in(spheres, nullptr, point, nullptr);
  return detail::nearest_result(spheres, best.id, point, max_distance, best);
}

std::size_t overlapping(SphereView spheres, Vec3 centre, float radius,
                        std::span<std::uint32_t> out) {
  detail::IdCollector ids{out.data(), out.size(), false};
  overlapping_in(spheres, nullptr, centre, radius, ids);
  ids.finish();
  return ids.total;
}

}  // namespace scalar

namespace detail {

Hit scalar_nearest(SphereView v, Vec3 point, float) {
  return nearest_in(v, nullptr, point, nullptr);
}
std::size_t scalar_overlapping(SphereView v, Vec3 centre, float radius, IdCollector& out) {
  return overlapping_in(v, nullptr, centre, radius, out);
}
// The tree's slots in leaf order, each with its id: the answers do not depend on the order
// (ties go by id), and padding slots (radius 0) are skipped as invalid.
Hit scalar_bvh_nearest(const BvhData& bvh, Vec3 point, float, std::size_t* slot) {
  return nearest_in(bvh.spheres, bvh.ids, point, slot);
}
std::size_t scalar_bvh_overlapping(const BvhData& bvh, Vec3 centre, float radius,
                                   IdCollector& out) {
  return overlapping_in(bvh.spheres, bvh.ids, centre, radius, out);
}

// Every pair of valid slots, the share's slots against all later ones: the contract's
// definition, one pair at a time, with the lower id's sphere as the ball.
void scalar_bvh_overlapping_pairs(const BvhData& bvh, std::size_t part, std::size_t parts,
                                  std::vector<IdPair>& out) {
  const SphereView v = bvh.spheres;
  const auto centre = [&](std::size_t s) { return Vec3{v.cx[s], v.cy[s], v.cz[s]}; };
  for (std::size_t s = v.count * part / parts; s < v.count * (part + 1) / parts; ++s) {
    if (!valid_sphere(centre(s), v.radius[s])) continue;
    for (std::size_t t = s + 1; t < v.count; ++t) {
      if (!valid_sphere(centre(t), v.radius[t])) continue;
      const bool s_lower = bvh.ids[s] < bvh.ids[t];
      const std::size_t ball = s_lower ? s : t, sphere = s_lower ? t : s;
      if (signed_distance(centre(ball), centre(sphere), v.radius[sphere]) < v.radius[ball])
        out.push_back({bvh.ids[ball], bvh.ids[sphere]});
    }
  }
}

}  // namespace detail
}  // namespace sphray
