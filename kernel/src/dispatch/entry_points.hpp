// The entry points of one instruction set, built from BruteForce<A> and the tree's walk over A.
// A per-ISA unit includes this and defines its table with make_entry_table<A>(isa).
#pragma once

#include <cstddef>

#include "all_hits/all_hits.hpp"
#include "brute/brute_force.hpp"
#include "brute/ray_lanes.hpp"
#include "bvh/scalar_walk.hpp"
#include "bvh/stream.hpp"
#include "bvh/traverse.hpp"
#include "dispatch/entry_table.hpp"
#include "dispatch/query_plan.hpp"
#include "point/overlap_pairs.hpp"
#include "point/point_queries.hpp"
#include "simd/isa_namespace.hpp"
#include "sphray/query.hpp"
#include "storage/ray_columns.hpp"
#include "surface/surface_lanes.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct EntryPoints {
  using Brute = BruteForce<A>;

  static Hit intersect(SphereView v, const Ray& ray) {
    return QueryPlan::scalar(v.count) ? scalar::intersect(v, ray) : Brute::intersect(v, ray);
  }
  static bool occluded(SphereView v, const Ray& ray) {
    return QueryPlan::scalar(v.count) ? scalar::occluded(v, ray) : Brute::occluded(v, ray);
  }
  // Rays: `const Ray*` or RayColumns, Hits: `Hit*` or HitColumns (storage/ray_columns.hpp).
  using Across = RayLanes<A>;
  template <class Rays, class Hits>
  static void brute_stream(SphereView v, Rays rays, Hits hits, std::size_t n) {
    if (QueryPlan::rays_across(v.count)) return Across::intersect_stream(v, rays, hits, n);
    if (QueryPlan::scalar(v.count)) {
      for (std::size_t i = 0; i < n; ++i)
        hits[i] = scalar::intersect(v, rays[i]);
      return;
    }
    for (std::size_t i = 0; i < n; ++i)
      hits[i] = Brute::intersect(v, rays[i]);
  }
  static void intersect_stream(SphereView v, const Ray* rays, Hit* hits, std::size_t n) {
    brute_stream(v, rays, hits, n);
  }
  static void intersect_arrays(SphereView v, const RayArrays& rays, const HitArrays& hits) {
    brute_stream(v, RayColumns{rays}, HitColumns{hits}, rays.count);
  }
  static void occluded_stream(SphereView v, const Ray* rays, bool* blocked, std::size_t n) {
    if (QueryPlan::rays_across(v.count)) return Across::occluded_stream(v, rays, blocked, n);
    for (std::size_t i = 0; i < n; ++i)
      blocked[i] = occluded(v, rays[i]);
  }
  static void intersect_across(SphereView v, const Ray* rays, Hit* hits, std::size_t n) {
    Across::intersect_stream(v, rays, hits, n);
  }
  static void occluded_across(SphereView v, const Ray* rays, bool* blocked, std::size_t n) {
    Across::occluded_stream(v, rays, blocked, n);
  }

  // A tree over so few spheres takes the scalar path too, so that it returns exactly what the
  // brute-force entries above return on the same spheres. A small tree, built flat, is brute
  // force on its own spheres (QueryPlan::brute_force_tree): slot i holds sphere i.
  // The same plan for float and double trees.
  using Tree = BvhTraversal<A>;
  template <class S>
  static BasicSphereView<S> flat_spheres(const BasicBvhData<S>& bvh) {
    BasicSphereView<S> v = bvh.spheres;  // padded to its slots, which are whole batches
    v.count = bvh.count;
    return v;
  }
  template <class S>
  static BasicHit<S> tree_intersect(const BasicBvhData<S>& bvh, const BasicRay<S>& ray) {
    if (QueryPlan::template scalar<S>(bvh.count)) return scalar_bvh_intersect(bvh, ray);
    if (QueryPlan::brute_force_tree(bvh))
      return BruteForce<A, S>::intersect(flat_spheres(bvh), ray);
    return BvhTraversal<A, S>::intersect(bvh, ray);
  }
  template <class S>
  static bool tree_occluded(const BasicBvhData<S>& bvh, const BasicRay<S>& ray) {
    if (QueryPlan::template scalar<S>(bvh.count)) return scalar_bvh_occluded(bvh, ray);
    if (QueryPlan::brute_force_tree(bvh)) return BruteForce<A, S>::occluded(flat_spheres(bvh), ray);
    return BvhTraversal<A, S>::occluded(bvh, ray);
  }
  static Hit bvh_intersect(const BvhData& bvh, const Ray& ray) { return tree_intersect(bvh, ray); }
  static bool bvh_occluded(const BvhData& bvh, const Ray& ray) { return tree_occluded(bvh, ray); }
  template <class Rays, class Hits>
  static void tree_stream(const BvhData& bvh, Rays rays, Hits hits, std::size_t n) {
    if (QueryPlan::scalar(bvh.count)) {
      for (std::size_t i = 0; i < n; ++i)
        hits[i] = scalar_bvh_intersect(bvh, rays[i]);
      return;
    }
    if (QueryPlan::brute_force_tree(bvh)) return brute_stream(flat_spheres(bvh), rays, hits, n);
    TreeStream<A>::intersect_stream(bvh, rays, hits, n);
  }
  static void bvh_intersect_stream(const BvhData& bvh, const Ray* rays, Hit* hits, std::size_t n) {
    tree_stream(bvh, rays, hits, n);
  }
  static void bvh_intersect_arrays(const BvhData& bvh, const RayArrays& rays,
                                   const HitArrays& hits) {
    tree_stream(bvh, RayColumns{rays}, HitColumns{hits}, rays.count);
  }
  static void bvh_occluded_stream(const BvhData& bvh, const Ray* rays, bool* blocked,
                                  std::size_t n) {
    if (QueryPlan::scalar(bvh.count)) return scalar_bvh_occluded_stream(bvh, rays, blocked, n);
    if (QueryPlan::brute_force_tree(bvh))
      return occluded_stream(flat_spheres(bvh), rays, blocked, n);
    TreeStream<A>::occluded_stream(bvh, rays, blocked, n);
  }

  // Every crossing: the SIMD path whatever the size, since it returns the scalar reference's
  // bits (the same roots) and a handful of spheres costs it no more than the scalar loop.
  static std::size_t intersect_all(SphereView v, const Ray& ray, Hit* hits, bool* exits,
                                   std::size_t capacity) {
    HitList list(hits, exits, capacity);
    return AllHits<A>::intersect_all(v, ray, list);
  }
  template <class S>
  static std::size_t bvh_intersect_all(const BasicBvhData<S>& bvh, const BasicRay<S>& ray,
                                       BasicHit<S>* hits, bool* exits, std::size_t capacity) {
    BasicHitList<S> list(hits, exits, capacity);
    return AllHits<A, S>::intersect_all(bvh, ray, list);
  }
  template <class S>
  static std::size_t bvh_intersect_nearest(const BasicBvhData<S>& bvh, const BasicRay<S>& ray,
                                           BasicHit<S>* hits, bool* exits, std::size_t capacity) {
    // The nearest crossing alone is the closest hit, bit for bit (docs/queries.md): its walk,
    // without a list to keep.
    if (capacity == 1 && exits == nullptr) {
      const BasicHit<S> hit = tree_intersect(bvh, ray);
      if (!hit.found()) return 0;
      hits[0] = hit;
      return 1;
    }
    BasicHitList<S> list(hits, exits, capacity);
    return AllHits<A, S>::intersect_nearest(bvh, ray, list);
  }

  // The point queries in float and double.
  template <class S>
  using Points = PointQueries<A, S>;
  template <class S>
  static BasicHit<S> nearest(BasicSphereView<S> v, BasicVec3<S> point, S) {
    return Points<S>::nearest(v, point);
  }
  template <class S>
  static std::size_t overlapping(BasicSphereView<S> v, BasicVec3<S> centre, S radius,
                                 IdCollector& out) {
    return Points<S>::overlapping(v, centre, radius, out);
  }
  template <class S>
  static BasicHit<S> bvh_nearest(const BasicBvhData<S>& bvh, BasicVec3<S> point, S max_distance,
                                 std::size_t* slot) {
    return Points<S>::nearest(bvh, point, max_distance, *slot);
  }
  template <class S>
  static std::size_t bvh_overlapping(const BasicBvhData<S>& bvh, BasicVec3<S> centre, S radius,
                                     IdCollector& out) {
    return Points<S>::overlapping(bvh, centre, radius, out);
  }
  template <class S>
  static void bvh_overlapping_pairs(const BasicBvhData<S>& bvh, std::size_t part, std::size_t parts,
                                    std::vector<IdPair>& out) {
    OverlapPairs<A, S>::find(bvh, part, parts, out);
  }

  // Double: the same plan as float's brute force, one ray at a time. The batches are a call of
  // their own, so that a few spheres' way to the scalar loop is a jump: inlined, the batches'
  // stack frame (aligned for vectors) was set up first, and cost three spheres a fifth of their
  // time on AVX-512.
  using BruteD = BruteForce<A, double>;
  [[gnu::noinline]] static Hitd batches_d(SphereViewd v, const Rayd& ray) {
    return BruteD::intersect(v, ray);
  }
  static Hitd intersect_d(SphereViewd v, const Rayd& ray) {
    return QueryPlan::scalar<double>(v.count) ? scalar::intersect(v, ray) : batches_d(v, ray);
  }
  static bool occluded_d(SphereViewd v, const Rayd& ray) {
    return QueryPlan::scalar<double>(v.count) ? scalar::occluded(v, ray) : BruteD::occluded(v, ray);
  }
  static void intersect_stream_d(SphereViewd v, const Rayd* rays, Hitd* hits, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
      hits[i] = intersect_d(v, rays[i]);
  }
  static void occluded_stream_d(SphereViewd v, const Rayd* rays, bool* blocked, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
      blocked[i] = occluded_d(v, rays[i]);
  }
  static std::size_t intersect_all_d(SphereViewd v, const Rayd& ray, Hitd* hits, bool* exits,
                                     std::size_t capacity) {
    BasicHitList<double> list(hits, exits, capacity);
    return AllHits<A, double>::intersect_all(v, ray, list);
  }

  // The double tree: float's plan, rays one at a time (no packets or walks in turns yet).
  using TreeD = BvhTraversal<A, double>;
  static Hitd bvh_intersect_d(const BvhDatad& bvh, const Rayd& ray) {
    return tree_intersect(bvh, ray);
  }
  static bool bvh_occluded_d(const BvhDatad& bvh, const Rayd& ray) {
    return tree_occluded(bvh, ray);
  }
  static void bvh_intersect_stream_d(const BvhDatad& bvh, const Rayd* rays, Hitd* hits,
                                     std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
      hits[i] = tree_intersect(bvh, rays[i]);
  }
  static void bvh_occluded_stream_d(const BvhDatad& bvh, const Rayd* rays, bool* blocked,
                                    std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
      blocked[i] = tree_occluded(bvh, rays[i]);
  }
};

template <class A>
constexpr EntryTable make_entry_table(Isa isa) {
  using E = EntryPoints<A>;
  return {isa,
          E::Brute::kWidth,
          &E::intersect,
          &E::occluded,
          &E::intersect_stream,
          &E::intersect_arrays,
          &E::occluded_stream,
          &E::intersect_across,
          &E::occluded_across,
          E::Tree::kWidth,
          &E::bvh_intersect,
          &E::bvh_occluded,
          &E::bvh_intersect_stream,
          &E::bvh_intersect_arrays,
          &E::bvh_occluded_stream,
          &E::intersect_all,
          &E::template bvh_intersect_all<float>,
          &E::template bvh_intersect_nearest<float>,
          &E::template nearest<float>,
          &E::template overlapping<float>,
          &E::template bvh_nearest<float>,
          &E::template bvh_overlapping<float>,
          &E::template bvh_overlapping_pairs<float>,
          &SurfaceLanes<A>::surfaces,
          &SurfaceLanes<A>::offset_origins,
          E::BruteD::kWidth,
          &E::intersect_d,
          &E::occluded_d,
          &E::intersect_stream_d,
          &E::occluded_stream_d,
          &E::intersect_all_d,
          E::TreeD::kWidth,
          &E::bvh_intersect_d,
          &E::bvh_occluded_d,
          &E::bvh_intersect_stream_d,
          &E::bvh_occluded_stream_d,
          &E::template bvh_intersect_all<double>,
          &E::template bvh_intersect_nearest<double>,
          &E::template nearest<double>,
          &E::template overlapping<double>,
          &E::template bvh_nearest<double>,
          &E::template bvh_overlapping<double>,
          &E::template bvh_overlapping_pairs<double>};
}

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
