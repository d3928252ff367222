// The scalar reference traversal of a SphereBVH: plain C++, one child box and one sphere at a
// time, every entered child visited (no ordering, no early culling beyond the box test). It
// shares only the layout with the SIMD traversal, and its leaves call scalar::intersect.
#pragma once

#include <cstddef>

#include "bvh/bvh_data.hpp"

namespace sphray::detail {

/// Children per node and spheres per leaf of the trees the scalar kernel queries.
inline constexpr std::size_t kScalarBvhWidth = 4;

Hit scalar_bvh_intersect(const BvhData& bvh, const Ray& ray);
bool scalar_bvh_occluded(const BvhData& bvh, const Ray& ray);
void scalar_bvh_intersect_stream(const BvhData& bvh, const Ray* rays, Hit* hits, std::size_t n);
void scalar_bvh_occluded_stream(const BvhData& bvh, const Ray* rays, bool* blocked, std::size_t n);

}  // namespace sphray::detail
