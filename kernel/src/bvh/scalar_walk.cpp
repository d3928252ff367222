#include "bvh/scalar_walk.hpp"

#include <cmath>
#include <cstdint>

#include "brute/validity.hpp"
#include "bvh/node.hpp"
#include "bvh/robust_slab.hpp"
#include "sphray/query.hpp"

namespace sphray::detail {
namespace {

using Node = SPHRAY_ISA_NAMESPACE::NodeView<const float>;
using SPHRAY_ISA_NAMESPACE::ChildRef;
using SPHRAY_ISA_NAMESPACE::kEntryScale;
using SPHRAY_ISA_NAMESPACE::kExitScale;

// Whether ray (valid) enters the box of child k of node before tmax: a slab whose distances
// are NaN (a zero direction component with the origin on a plane) does not bound the ray.
bool enters(const Node& node, std::size_t k, const Ray& ray, float tmax) {
  float tnear = ray.tmin, tfar = INFINITY;
  for (int axis = 0; axis < 3; ++axis) {
    const float o = ray.origin[axis], inv = 1.0f / ray.dir[axis];
    float t0 = (node.lo(axis, k) - o) * inv;
    float t1 = (node.hi(axis, k) - o) * inv;
    if (std::signbit(ray.dir[axis])) std::swap(t0, t1);
    if (t0 > tnear) tnear = t0;
    if (t1 < tfar) tfar = t1;
  }
  // Widened by 2 gamma(3) of each end's magnitude: scaling tfar alone is conservative only for
  // tfar >= 0, and a negative tmin lets the ray meet boxes behind its origin.
  tnear *= tnear >= 0.0f ? kEntryScale : kExitScale;
  tfar *= tfar >= 0.0f ? kExitScale : kEntryScale;
  return tnear <= tfar && tnear <= tmax;
}

// Visits every leaf whose box the ray enters; leaf(first sphere, sphere count) returns true to
// stop.
template <class Leaf>
void visit(const BvhData& bvh, const Ray& ray, const float& tmax, Leaf&& leaf) {
  // Invalid rays must not reach the box test: a NaN origin makes every slab NaN, which bounds
  // nothing, so the ray would "enter" even the empty child slots and follow their references
  // far outside the node array.
  if (bvh.node_count == 0 || !valid_ray(ray)) return;
  const std::size_t w = bvh.width;
  ChildRef stack[kBvhMaxDepth * (kScalarBvhWidth - 1) + 1];
  std::size_t top = 0;
  stack[top++] = ChildRef::node(0);
  while (top > 0) {
    const ChildRef ref = stack[--top];
    if (ref.is_leaf()) {
      if (leaf(ref.first(w), ref.count(w))) return;
      continue;
    }
    const Node node(bvh.nodes, ref.node_index(), w);
    for (std::size_t k = 0; k < w; ++k)
      if (enters(node, k, ray, tmax)) stack[top++] = node.ref(k);
  }
}

SphereView one_sphere(const SphereView& v, std::size_t i) {
  return {
      v.cx + i, v.cy + i, v.cz + i, v.radius + i, 1, 0, v.mask != nullptr ? v.mask + i : nullptr};
}

// Visits the one leaf of a tree over at most width spheres, or every leaf the ray enters. The
// one leaf is read directly, as brute force reads a view, rather than after a test of the
// root's mostly empty child boxes one by one.
template <class Leaf>
void visit_leaves(const BvhData& bvh, const Ray& ray, const float& tmax, Leaf&& leaf) {
  if (bvh.count <= bvh.width)
    leaf(0, bvh.count);
  else
    visit(bvh, ray, tmax, leaf);
}

}  // namespace

Hit scalar_bvh_intersect(const BvhData& bvh, const Ray& ray) {
  Hit best{ray.tmax, kNoHit};
  visit_leaves(bvh, ray, best.t, [&](std::size_t first, std::size_t count) {
    for (std::size_t i = first; i < first + count; ++i) {
      // The sphere's own hit within the ray's full interval, then the contract's order: the
      // smaller t, and on equal t the lower id.
      const Hit h = scalar::intersect(one_sphere(bvh.spheres, i), ray);
      if (!h.found()) continue;
      SPHRAY_ISA_NAMESPACE::keep_closer(best, h.t, bvh.ids[i]);
    }
    return false;
  });
  return best;
}

bool scalar_bvh_occluded(const BvhData& bvh, const Ray& ray) {
  bool hit = false;
  visit_leaves(bvh, ray, ray.tmax, [&](std::size_t first, std::size_t count) {
    for (std::size_t i = first; i < first + count && !hit; ++i)
      hit = scalar::occluded(one_sphere(bvh.spheres, i), ray);
    return hit;
  });
  return hit;
}

void scalar_bvh_intersect_stream(const BvhData& bvh, const Ray* rays, Hit* hits, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    hits[i] = scalar_bvh_intersect(bvh, rays[i]);
}

void scalar_bvh_occluded_stream(const BvhData& bvh, const Ray* rays, bool* blocked, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    blocked[i] = scalar_bvh_occluded(bvh, rays[i]);
}

}  // namespace sphray::detail
