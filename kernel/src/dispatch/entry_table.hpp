// The entry-point tables of the instruction sets this build has, each defined in its own
// translation unit compiled with exactly that instruction set's flags (see CMakeLists.txt), and
// the dispatcher's choice among them (dispatch.cpp).
#pragma once

#include <cstddef>
#include <type_traits>
#include <vector>

#include "sphray/isa.hpp"
#include "sphray/point_queries.hpp"
#include "sphray/ray.hpp"
#include "sphray/ray_arrays.hpp"
#include "sphray/spheres.hpp"

namespace sphray::detail {

template <Scalar S>
struct BasicBvhData;  // bvh/bvh_data.hpp
using BvhData = BasicBvhData<float>;
using BvhDatad = BasicBvhData<double>;
struct IdCollector;  // point/id_collector.hpp

/// The entry points of one instruction set. Same contract as query.hpp. Internal: tests and
/// benchmarks reach a given instruction set through it (the sphray_kernel_internals target).
struct EntryTable {
  Isa isa;
  std::size_t width;
  Hit (*intersect)(SphereView spheres, const Ray& ray);
  bool (*occluded)(SphereView spheres, const Ray& ray);
  /// hits[i] = intersect(spheres, rays[i]) for i < count.
  void (*intersect_stream)(SphereView spheres, const Ray* rays, Hit* hits, std::size_t count);
  /// The same stream with rays and hits as arrays per quantity (ray_arrays.hpp): hit i is
  /// intersect(spheres, rays.at(i)) for i < rays.count; hits.count == rays.count.
  void (*intersect_arrays)(SphereView spheres, const RayArrays& rays, const HitArrays& hits);
  /// blocked[i] = occluded(spheres, rays[i]) for i < count.
  void (*occluded_stream)(SphereView spheres, const Ray* rays, bool* blocked, std::size_t count);
  /// The two streams above with the rays across the lanes whatever the view's size
  /// (brute/ray_lanes.hpp), where the query plan would take them only for few spheres: the
  /// same answers, for tests and benchmarks.
  void (*intersect_across)(SphereView spheres, const Ray* rays, Hit* hits, std::size_t count);
  void (*occluded_across)(SphereView spheres, const Ray* rays, bool* blocked, std::size_t count);
  /// The SphereBVH entries (bvh.hpp) for trees of bvh_width children per node and spheres per
  /// leaf batch.
  std::size_t bvh_width;
  Hit (*bvh_intersect)(const BvhData& bvh, const Ray& ray);
  bool (*bvh_occluded)(const BvhData& bvh, const Ray& ray);
  void (*bvh_intersect_stream)(const BvhData& bvh, const Ray* rays, Hit* hits, std::size_t count);
  void (*bvh_intersect_arrays)(const BvhData& bvh, const RayArrays& rays, const HitArrays& hits);
  /// blocked[i] = bvh_occluded(bvh, rays[i]) for i < count.
  void (*bvh_occluded_stream)(const BvhData& bvh, const Ray* rays, bool* blocked,
                              std::size_t count);
  /// Every crossing (all_hits.hpp): the nearest capacity of them into hits (and exits, if not
  /// null), sorted; returns how many there are in all.
  std::size_t (*intersect_all)(SphereView spheres, const Ray& ray, Hit* hits, bool* exits,
                               std::size_t capacity);
  std::size_t (*bvh_intersect_all)(const BvhData& bvh, const Ray& ray, Hit* hits, bool* exits,
                                   std::size_t capacity);
  /// The nearest capacity (at least 1) crossings alone, as bvh_intersect_all's first ones, the
  /// walk bounded by the last kept; returns how many it wrote.
  std::size_t (*bvh_intersect_nearest)(const BvhData& bvh, const Ray& ray, Hit* hits, bool* exits,
                                       std::size_t capacity);
  /// The point queries (point_queries.hpp): the nearest sphere as {signed distance, id}
  /// ({+inf, kNoHit} for none; the caller applies max_distance, which may only prune), and the
  /// spheres a ball overlaps, into out; returns their number.
  Hit (*nearest)(SphereView spheres, Vec3 point, float max_distance);
  std::size_t (*overlapping)(SphereView spheres, Vec3 centre, float radius, IdCollector& out);
  /// slot: where the nearest sphere sits in the tree's arrays (bvh.spheres).
  Hit (*bvh_nearest)(const BvhData& bvh, Vec3 point, float max_distance, std::size_t* slot);
  std::size_t (*bvh_overlapping)(const BvhData& bvh, Vec3 centre, float radius, IdCollector& out);
  /// Part `part` of `parts` of the tree's overlapping pairs (overlapping_pairs()), appended.
  void (*bvh_overlapping_pairs)(const BvhData& bvh, std::size_t part, std::size_t parts,
                                std::vector<IdPair>& out);
  /// surfaces() and offset_origins() (query.hpp), their arguments checked.
  void (*surfaces)(SphereView spheres, const RayArrays& rays, const HitArrays& hits,
                   const SurfaceArrays& out);
  void (*offset_origins)(const SurfaceArrays& surfaces, const VectorArrays& dirs,
                         const VectorOutArrays& origins);
  /// The brute-force queries and streams in double (docs/double.md), width doubles per step.
  std::size_t width_d;
  Hitd (*intersect_d)(SphereViewd spheres, const Rayd& ray);
  bool (*occluded_d)(SphereViewd spheres, const Rayd& ray);
  void (*intersect_stream_d)(SphereViewd spheres, const Rayd* rays, Hitd* hits, std::size_t count);
  void (*occluded_stream_d)(SphereViewd spheres, const Rayd* rays, bool* blocked,
                            std::size_t count);
  std::size_t (*intersect_all_d)(SphereViewd spheres, const Rayd& ray, Hitd* hits, bool* exits,
                                 std::size_t capacity);
  /// The SphereBVHd entries: trees of bvh_width_d children per node and spheres per leaf (the
  /// float trees' width: a leaf is bvh_width_d / width_d batches of doubles).
  std::size_t bvh_width_d;
  Hitd (*bvh_intersect_d)(const BvhDatad& bvh, const Rayd& ray);
  bool (*bvh_occluded_d)(const BvhDatad& bvh, const Rayd& ray);
  void (*bvh_intersect_stream_d)(const BvhDatad& bvh, const Rayd* rays, Hitd* hits,
                                 std::size_t count);
  void (*bvh_occluded_stream_d)(const BvhDatad& bvh, const Rayd* rays, bool* blocked,
                                std::size_t count);
  std::size_t (*bvh_intersect_all_d)(const BvhDatad& bvh, const Rayd& ray, Hitd* hits, bool* exits,
                                     std::size_t capacity);
  std::size_t (*bvh_intersect_nearest_d)(const BvhDatad& bvh, const Rayd& ray, Hitd* hits,
                                         bool* exits, std::size_t capacity);
  /// The point queries in double, as their float forms above.
  Hitd (*nearest_d)(SphereViewd spheres, Vec3d point, double max_distance);
  std::size_t (*overlapping_d)(SphereViewd spheres, Vec3d centre, double radius, IdCollector& out);
  Hitd (*bvh_nearest_d)(const BvhDatad& bvh, Vec3d point, double max_distance, std::size_t* slot);
  std::size_t (*bvh_overlapping_d)(const BvhDatad& bvh, Vec3d centre, double radius,
                                   IdCollector& out);
  void (*bvh_overlapping_pairs_d)(const BvhDatad& bvh, std::size_t part, std::size_t parts,
                                  std::vector<IdPair>& out);
};

/// Of an entry point's float and double forms (intersect and intersect_d, ...), the one for S.
template <Scalar S, class Float, class Double>
auto in_precision(Float float_entry, Double double_entry) {
  if constexpr (std::is_same_v<S, float>)
    return float_entry;
  else
    return double_entry;
}

/// The kernel for isa, or nullptr if this build lacks it or this machine cannot run it.
const EntryTable* find_entries(Isa isa);
/// The kernel of active_isa().
const EntryTable& active_entries();
/// The kernel the brute-force queries in query.hpp use for a view of sphere_count spheres:
/// active_entries(), except that a view too small to fill two thirds of its batch goes to the
/// widest narrower instruction set it does fill (a batch costs its full width whatever it
/// holds), and a view of fewer than two spheres to the scalar kernel. All of them return the same
/// hits, bit for bit.
const EntryTable& entries_for_size(std::size_t sphere_count);

extern const EntryTable kScalarEntries;
#if SPHRAY_HAS_SSE4_2
extern const EntryTable kSse42Entries;
#endif
#if SPHRAY_HAS_AVX2
extern const EntryTable kAvx2Entries;
#endif
#if SPHRAY_HAS_AVX512
extern const EntryTable kAvx512Entries;
#endif
#if SPHRAY_HAS_NEON
extern const EntryTable kNeonEntries;
#endif

}  // namespace sphray::detail
