#include "bvh/scalar_walk.hpp"

#include <cmath>
#include <cstdint>
#include <limits>

#include "brute/validity.hpp"
#include "bvh/node.hpp"
#include "bvh/robust_slab.hpp"
#include "sphray/query.hpp"

namespace sphray::detail {
namespace {

using Node = SPHRAY_ISA_NAMESPACE::NodeView<const float>;
using SPHRAY_ISA_NAMESPACE::ChildRef;
using SPHRAY_ISA_NAMESPACE::SlabScale;

// Whether ray (valid) enters the box of child k of node before tmax: a slab whose distances
// are NaN (a zero direction component with the origin on a plane) does not bound the ray. A
// double ray meets the float planes exactly widened.
template <class S>
bool enters(const Node& node, std::size_t k, const BasicRay<S>& ray, S tmax) {
  S tnear = ray.tmin, tfar = std::numeric_limits<S>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const S o = ray.origin[axis], inv = S(1) / ray.dir[axis];
    S t0 = (S(node.lo(axis, k)) - o) * inv;
    S t1 = (S(node.hi(axis, k)) - o) * inv;
    if (std::signbit(ray.dir[axis])) std::swap(t0, t1);
    if (t0 > tnear) tnear = t0;
    if (t1 < tfar) tfar = t1;
  }
  // Widened by 2 gamma(3) of each end's magnitude: scaling tfar alone is conservative only for
  // tfar >= 0, and a negative tmin lets the ray meet boxes behind its origin.
  tnear *= tnear >= S(0) ? SlabScale<S>::kEntry : SlabScale<S>::kExit;
  tfar *= tfar >= S(0) ? SlabScale<S>::kExit : SlabScale<S>::kEntry;
  return tnear <= tfar && tnear <= tmax;
}

// Visits every leaf whose box the ray enters; leaf(first sphere, sphere count) returns true to
// stop.
template <class S, class Leaf>
void visit(const BasicBvhData<S>& bvh, const BasicRay<S>& ray, const S& tmax, Leaf&& leaf) {
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

template <class S>
BasicSphereView<S> one_sphere(const BasicSphereView<S>& v, std::size_t i) {
  return {
      v.cx + i, v.cy + i, v.cz + i, v.radius + i, 1, 0, v.mask != nullptr ? v.mask + i : nullptr};
}

// Visits the one leaf of a tree over at most width spheres, or every leaf the ray enters. The
// one leaf is read directly, as brute force reads a view, rather than after a test of the
// root's mostly empty child boxes one by one.
template <class S, class Leaf>
void visit_leaves(const BasicBvhData<S>& bvh, const BasicRay<S>& ray, const S& tmax, Leaf&& leaf) {
  if (bvh.count <= bvh.width)
    leaf(0, bvh.count);
  else
    visit(bvh, ray, tmax, leaf);
}

}  // namespace

template <Scalar S>
BasicHit<S> scalar_bvh_intersect(const BasicBvhData<S>& bvh, const BasicRay<S>& ray) {
  BasicHit<S> best{ray.tmax, kNoHit};
  visit_leaves(bvh, ray, best.t, [&](std::size_t first, std::size_t count) {
    for (std::size_t i = first; i < first + count; ++i) {
      // The sphere's own hit within the ray's full interval, then the contract's order: the
      // smaller t, and on equal t the lower id.
      const BasicHit<S> h = scalar::intersect(one_sphere(bvh.spheres, i), ray);
      if (!h.found()) continue;
      SPHRAY_ISA_NAMESPACE::keep_closer(best, h.t, bvh.ids[i]);
    }
    return false;
  });
  return best;
}

template <Scalar S>
bool scalar_bvh_occluded(const BasicBvhData<S>& bvh, const BasicRay<S>& ray) {
  bool hit = false;
  visit_leaves(bvh, ray, ray.tmax, [&](std::size_t first, std::size_t count) {
    for (std::size_t i = first; i < first + count && !hit; ++i)
      hit = scalar::occluded(one_sphere(bvh.spheres, i), ray);
    return hit;
  });
  return hit;
}

template <Scalar S>
void scalar_bvh_intersect_stream(const BasicBvhData<S>& bvh, const BasicRay<S>* rays,
                                 BasicHit<S>* hits, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    hits[i] = scalar_bvh_intersect(bvh, rays[i]);
}

template <Scalar S>
void scalar_bvh_occluded_stream(const BasicBvhData<S>& bvh, const BasicRay<S>* rays, bool* blocked,
                                std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    blocked[i] = scalar_bvh_occluded(bvh, rays[i]);
}

#define SPHRAY_SCALAR_WALK(S)                                                                 \
  template BasicHit<S> scalar_bvh_intersect(const BasicBvhData<S>&, const BasicRay<S>&);      \
  template bool scalar_bvh_occluded(const BasicBvhData<S>&, const BasicRay<S>&);              \
  template void scalar_bvh_intersect_stream(const BasicBvhData<S>&, const BasicRay<S>*,       \
                                            BasicHit<S>*, std::size_t);                       \
  template void scalar_bvh_occluded_stream(const BasicBvhData<S>&, const BasicRay<S>*, bool*, \
                                           std::size_t);
SPHRAY_SCALAR_WALK(float)
SPHRAY_SCALAR_WALK(double)
#undef SPHRAY_SCALAR_WALK

}  // namespace sphray::detail
