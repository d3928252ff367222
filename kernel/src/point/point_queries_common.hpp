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
template <Scalar S>
BasicNearest<S> nearest_result(BasicSphereView<S> spheres, std::size_t slot, BasicVec3<S> point,
                               S max_distance, BasicHit<S> best);

/// The scalar kernel's point entries, in float and double (point_reference.cpp).
template <Scalar S>
BasicHit<S> scalar_nearest(BasicSphereView<S> v, BasicVec3<S> point, S max_distance);
template <Scalar S>
std::size_t scalar_overlapping(BasicSphereView<S> v, BasicVec3<S> centre, S radius,
                               IdCollector& out);
template <Scalar S>
BasicHit<S> scalar_bvh_nearest(const BasicBvhData<S>& bvh, BasicVec3<S> point, S max_distance,
                               std::size_t* slot);
template <Scalar S>
std::size_t scalar_bvh_overlapping(const BasicBvhData<S>& bvh, BasicVec3<S> centre, S radius,
                                   IdCollector& out);
template <Scalar S>
void scalar_bvh_overlapping_pairs(const BasicBvhData<S>& bvh, std::size_t part, std::size_t parts,
                                  std::vector<IdPair>& out);

}  // namespace sphray::detail
