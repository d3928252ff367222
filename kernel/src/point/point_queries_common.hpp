// What every form of the point queries shares outside the kernels: the public answer made from
// a kernel's {distance, id}, and the scalar kernel's entries (point_reference.cpp).
#pragma once

#include <cstddef>
#include <vector>

#include "sphray/point_queries.hpp"

namespace sphray::detail {

template <Scalar S>
struct BasicBvhData;
using BvhData = BasicBvhData<float>;
using BvhDatad = BasicBvhData<double>;
struct IdCollector;

/// The Nearest for a kernel's answer best, whose sphere is at index slot of spheres: a miss
/// unless best.t <= max_distance, else with the closest surface point.
Nearest nearest_result(SphereView spheres, std::size_t slot, Vec3 point, float max_distance,
                       Hit best);

Hit scalar_nearest(SphereView v, Vec3 point, float max_distance);
std::size_t scalar_overlapping(SphereView v, Vec3 centre, float radius, IdCollector& out);
Hit scalar_bvh_nearest(const BvhData& bvh, Vec3 point, float max_distance, std::size_t* slot);
std::size_t scalar_bvh_overlapping(const BvhData& bvh, Vec3 centre, float radius, IdCollector& out);
void scalar_bvh_overlapping_pairs(const BvhData& bvh, std::size_t part, std::size_t parts,
                                  std::vector<IdPair>& out);

}  // namespace sphray::detail
