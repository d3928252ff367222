// The point queries' scalar reference, one sphere at a time, in float and double, and the
// scalar kernel's entries for them. The signed distance is point_lanes.hpp's, operation for
// operation.
#include <algorithm>
#include <cmath>
#include <limits>
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

template <Scalar S>
bool finite(BasicVec3<S> p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

template <Scalar S>
S distance(BasicVec3<S> p, BasicVec3<S> c) {
  const BasicVec3<S> g = c - p;
  return std::sqrt(g.x * g.x + (g.y * g.y + g.z * g.z));
}

template <Scalar S>
S signed_distance(BasicVec3<S> p, BasicVec3<S> c, S r) {
  return distance(p, c) - r;
}

// Visits slot i of n with its id: a view's own (ids = nullptr) or a tree's leaf slots.
// Invalid spheres are passed over but still counted in the slot index the visitor keeps.
template <Scalar S, class Visit>
void each_sphere(BasicSphereView<S> v, const std::uint32_t* ids, Visit&& visit) {
  const std::size_t n = ids != nullptr ? v.count : std::min<std::size_t>(v.count, kNoHit);
  for (std::size_t i = 0; i < n; ++i) {
    const BasicVec3<S> c{v.cx[i], v.cy[i], v.cz[i]};
    const bool valid = valid_sphere(c, v.radius[i]);
    if (visit(valid, c, v.radius[i], ids != nullptr ? ids[i] : static_cast<std::uint32_t>(i)))
      return;
  }
}

template <Scalar S>
BasicHit<S> nearest_in(BasicSphereView<S> v, const std::uint32_t* ids, BasicVec3<S> point,
                       std::size_t* slot) {
  constexpr S kInf = std::numeric_limits<S>::infinity();
  BasicHit<S> best{kInf, kNoHit};
  if (!finite(point)) return best;
  std::size_t i = 0;
  each_sphere(v, ids, [&](bool valid, BasicVec3<S> c, S r, std::uint32_t id) {
    const std::size_t at = i++;
    if (!valid) return false;
    const S d = signed_distance(point, c, r);
    if (d < best.t || (d == best.t && best.id != kNoHit && id < best.id)) {
      best = {d, id};
      if (slot != nullptr) *slot = at;
    }
    return false;
  });
  return best.t < kInf ? best : BasicHit<S>{kInf, kNoHit};
}

template <Scalar S>
std::size_t overlapping_in(BasicSphereView<S> v, const std::uint32_t* ids, BasicVec3<S> centre,
                           S radius, detail::IdCollector& out) {
  if (!finite(centre) || !(radius >= S(0))) return 0;
  each_sphere(v, ids, [&](bool valid, BasicVec3<S> c, S r, std::uint32_t id) {
    return valid && signed_distance(centre, c, r) < radius && out.add(id);
  });
  return out.total;
}

template <Scalar S>
BasicNearest<S> reference_nearest(BasicSphereView<S> spheres, BasicVec3<S> point, S max_distance) {
  const BasicHit<S> best = nearest_in(spheres, nullptr, point, nullptr);
  return detail::nearest_result(spheres, best.id, point, max_distance, best);
}

template <Scalar S>
std::size_t reference_overlapping(BasicSphereView<S> spheres, BasicVec3<S> centre, S radius,
                                  std::span<std::uint32_t> out) {
  detail::IdCollector ids{out.data(), out.size(), false};
  overlapping_in(spheres, nullptr, centre, radius, ids);
  ids.finish();
  return ids.total;
}

}  // namespace

namespace scalar {

Nearest nearest(SphereView spheres, Vec3 point, float max_distance) {
  return reference_nearest(spheres, point, max_distance);
}
Nearestd nearest(SphereViewd spheres, Vec3d point, double max_distance) {
  return reference_nearest(spheres, point, max_distance);
}

std::size_t overlapping(SphereView spheres, Vec3 centre, float radius,
                        std::span<std::uint32_t> out) {
  return reference_overlapping(spheres, centre, radius, out);
}
std::size_t overlapping(SphereViewd spheres, Vec3d centre, double radius,
                        std::span<std::uint32_t> out) {
  return reference_overlapping(spheres, centre, radius, out);
}

}  // namespace scalar

namespace detail {

template <Scalar S>
BasicHit<S> scalar_nearest(BasicSphereView<S> v, BasicVec3<S> point, S) {
  return nearest_in(v, nullptr, point, nullptr);
}
template <Scalar S>
std::size_t scalar_overlapping(BasicSphereView<S> v, BasicVec3<S> centre, S radius,
                               IdCollector& out) {
  return overlapping_in(v, nullptr, centre, radius, out);
}
// The tree's slots in leaf order, each with its id: the answers do not depend on the order
// (ties go by id), and padding slots (radius 0) are skipped as invalid.
template <Scalar S>
BasicHit<S> scalar_bvh_nearest(const BasicBvhData<S>& bvh, BasicVec3<S> point, S,
                               std::size_t* slot) {
  return nearest_in(bvh.spheres, bvh.ids, point, slot);
}
template <Scalar S>
std::size_t scalar_bvh_overlapping(const BasicBvhData<S>& bvh, BasicVec3<S> centre, S radius,
                                   IdCollector& out) {
  return overlapping_in(bvh.spheres, bvh.ids, centre, radius, out);
}

template Hit scalar_nearest(SphereView, Vec3, float);
template Hitd scalar_nearest(SphereViewd, Vec3d, double);
template std::size_t scalar_overlapping(SphereView, Vec3, float, IdCollector&);
template std::size_t scalar_overlapping(SphereViewd, Vec3d, double, IdCollector&);
template Hit scalar_bvh_nearest(const BvhData&, Vec3, float, std::size_t*);
template Hitd scalar_bvh_nearest(const BvhDatad&, Vec3d, double, std::size_t*);
template std::size_t scalar_bvh_overlapping(const BvhData&, Vec3, float, IdCollector&);
template std::size_t scalar_bvh_overlapping(const BvhDatad&, Vec3d, double, IdCollector&);

// Every pair of valid slots, the share's slots against all later ones: the contract's
// definition, one pair at a time, with the lower id's sphere as the ball.
template <Scalar S>
void scalar_bvh_overlapping_pairs(const BasicBvhData<S>& bvh, std::size_t part, std::size_t parts,
                                  std::vector<IdPair>& out) {
  const BasicSphereView<S> v = bvh.spheres;
  const auto centre = [&](std::size_t s) { return BasicVec3<S>{v.cx[s], v.cy[s], v.cz[s]}; };
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

template void scalar_bvh_overlapping_pairs(const BvhData&, std::size_t, std::size_t,
                                           std::vector<IdPair>&);
template void scalar_bvh_overlapping_pairs(const BvhDatad&, std::size_t, std::size_t,
                                           std::vector<IdPair>&);

}  // namespace detail
}  // namespace sphray
