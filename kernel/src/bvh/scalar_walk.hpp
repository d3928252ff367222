// The scalar reference traversal of a SphereBVH: plain C++, one child box and one sphere at a
// time, every entered child visited (no ordering, no early culling beyond the box test). It
// shares only the layout with the SIMD traversal, and its leaves call scalar::intersect.
#pragma once

#include <cstddef>

#include "bvh/bvh_data.hpp"

namespace sphray::detail {

/// Children per node and spheres per leaf of the trees the scalar kernel queries.
inline constexpr std::size_t kScalarBvhWidth = 4;

/// For float and double trees (explicitly instantiated in scalar_walk.cpp).
template <Scalar S>
BasicHit<S> scalar_bvh_intersect(const BasicBvhData<S>& bvh, const BasicRay<S>& ray);
template <Scalar S>
bool scalar_bvh_occluded(const BasicBvhData<S>& bvh, const BasicRay<S>& ray);
template <Scalar S>
void scalar_bvh_intersect_stream(const BasicBvhData<S>& bvh, const BasicRay<S>* rays,
                                 BasicHit<S>* hits, std::size_t n);
template <Scalar S>
void scalar_bvh_occluded_stream(const BasicBvhData<S>& bvh, const BasicRay<S>* rays, bool* blocked,
                                std::size_t n);

}  // namespace sphray::detail
