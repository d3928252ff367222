// SphereBVH: a wide bounding volume hierarchy over spheres, for scenes too large for brute force;
// SphereBVHd, the same over double spheres (docs/double.md).
//
// Built once from a SphereView, it keeps its own copy of the spheres (in leaf order, with their
// original ids), so the view may change or go away afterwards. Queries follow the contract of
// query.hpp exactly: the same id and t as brute force on the same spheres, bit for bit, ties to
// the lower id, the same handling of invalid rays and spheres.
//
//   sphray::SphereBVH bvh(spheres.view());
//   sphray::Hit hit = sphray::intersect(bvh, ray);
//   ...  // spheres moved, same count:
//   bvh.refit(spheres.view());
//
// A node holds as many children as one SIMD batch of floats has lanes, and a leaf as many
// spheres (a double tree too: its nodes are a float tree's, docs/double.md): the tree is laid
// out for one instruction set, bvh_isa() unless another is given, and queried with that set's
// kernel. Queries are const and thread-safe; build and refit are not queries.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>

#include "sphray/api.h"
#include "sphray/isa.hpp"
#include "sphray/ray.hpp"
#include "sphray/ray_arrays.hpp"
#include "sphray/spheres.hpp"

namespace sphray {

namespace detail {
struct BvhAccess;   // the library's view of a tree's arrays (src/bvh/bvh_data.hpp)
struct EntryTable;  // an instruction set's entry points (src/dispatch/entry_table.hpp)
}  // namespace detail

/// How to build a SphereBVH.
struct BvhBuildOptions {
  /// Threads the builder may use; 0: all. The tree is the same whatever this is.
  unsigned threads = 0;
  /// Ranges of fewer spheres than this (at least 1024) are built by one thread; larger ones
  /// are binned, partitioned and split into tasks in parallel. The tree is the same for the
  /// same value whatever the thread count; another value may order the spheres within a leaf
  /// differently (never the results of a query).
  std::size_t parallel_min = 16384;
};

/// Called now and then during a build, from any of its threads (several may call at once), with
/// the fraction of the spheres placed in the tree so far, 0 to 1, last with 1 once it is built
/// (as Embree's progress monitor). Returning false stops the build: the constructor throws
/// BuildCancelled. An exception it throws leaves the constructor the same way.
using BuildProgress = std::function<bool(double done)>;

/// What a SphereBVH constructor throws when its BuildProgress returned false.
class SPHRAY_API BuildCancelled : public std::runtime_error {
 public:
  BuildCancelled();
};

/// A tree over spheres of scalar S: SphereBVH (float) or SphereBVHd (double, docs/double.md).
template <Scalar S>
class SPHRAY_API BasicSphereBVH {
 public:
  using View = BasicSphereView<S>;

  /// An empty tree (no spheres), for the active instruction set.
  BasicSphereBVH();
  /// Builds over spheres for the active instruction set. Throws std::length_error when the
  /// tree's sphere slots would reach 2^31: each leaf takes W slots (W the instruction set's
  /// float batch width, 16 for AVX-512, in float and double trees alike) however few spheres it
  /// holds, so the limit is met before 2^31 spheres. Below 2^31 / W spheres (2^27 with
  /// AVX-512, 2^28 with AVX2) a build never meets it; above, it depends on how full the leaves
  /// come out.
  explicit BasicSphereBVH(View spheres, BvhBuildOptions options = {});
  /// Builds over spheres for isa. Throws std::invalid_argument if find_entries(isa) is null or
  /// isa is not one of the Isa enumerators.
  BasicSphereBVH(View spheres, Isa isa, BvhBuildOptions options = {});
  /// Builds over spheres for the active instruction set, reporting to progress, which may stop
  /// the build (a Ctrl-C, a deadline). The tree is the same as without it.
  BasicSphereBVH(View spheres, BvhBuildOptions options, const BuildProgress& progress);

  /// A moved-from tree is the empty tree of the same instruction set: size() 0, every query a
  /// miss, refit() with an empty view only.
  BasicSphereBVH(BasicSphereBVH&&) noexcept;
  BasicSphereBVH& operator=(BasicSphereBVH&&) noexcept;
  ~BasicSphereBVH();

  /// Takes the new centres and radii of the same spheres (same count, same ids) and updates the
  /// boxes, keeping the tree's shape: much cheaper than a rebuild, but the tree gets slower as
  /// spheres drift far from where they were built. Throws std::invalid_argument if the count
  /// differs.
  void refit(View spheres);

  /// The number of spheres (the view's count at build time).
  std::size_t size() const;
  /// The instruction set the tree is laid out for and queried with.
  Isa isa() const;
  /// Bytes held: the sphere copy, the ids and the nodes. memory_bytes() / size() is the
  /// figure docs/bvh.md reports as bytes per sphere.
  std::size_t memory_bytes() const;

 private:
  friend struct detail::BvhAccess;
  struct Storage;
  std::unique_ptr<Storage> storage_;  // null once moved from: the empty tree
  const detail::EntryTable* entries_;
};

using SphereBVH = BasicSphereBVH<float>;
using SphereBVHd = BasicSphereBVH<double>;
extern template class BasicSphereBVH<float>;
extern template class BasicSphereBVH<double>;

/// Closest hit of ray among the tree's spheres: the same result as intersect(view, ray) on the
/// spheres it was built (or last refitted) from.
SPHRAY_API Hit intersect(const SphereBVH& bvh, const Ray& ray);

/// True if any sphere is hit in (tmin, tmax).
SPHRAY_API bool occluded(const SphereBVH& bvh, const Ray& ray);

/// hits[i] = intersect(bvh, rays[i]). Coherent rays (camera rays in rows or tiles) go through
/// the tree in packets, the others one at a time; every hit is the single-ray call's. Throws
/// std::length_error unless hits.size() == rays.size().
SPHRAY_API void intersect(const SphereBVH& bvh, std::span<const Ray> rays, std::span<Hit> hits);

/// The same stream with rays and hits as arrays per quantity (ray_arrays.hpp): the same path
/// through the tree, packets included, and the same hits bit for bit; the checks of
/// intersect(SphereView, const RayArrays&, const HitArrays&).
SPHRAY_API void intersect(const SphereBVH& bvh, const RayArrays& rays, const HitArrays& hits);

/// blocked[i] = occluded(bvh, rays[i]). Throws std::length_error unless
/// blocked.size() == rays.size(). Coherent rays, such as shadow rays towards one light from
/// neighbouring pixels' hits, go through the tree in packets.
SPHRAY_API void occluded(const SphereBVH& bvh, std::span<const Ray> rays, std::span<bool> blocked);

/// The same queries in double (docs/double.md): the same contract as brute force in double on
/// the tree's spheres, bit for bit. The streams take the rays one at a time (no packets yet).
SPHRAY_API Hitd intersect(const SphereBVHd& bvh, const Rayd& ray);
SPHRAY_API bool occluded(const SphereBVHd& bvh, const Rayd& ray);
SPHRAY_API void intersect(const SphereBVHd& bvh, std::span<const Rayd> rays, std::span<Hitd> hits);
SPHRAY_API void intersect(const SphereBVHd& bvh, const RayArraysd& rays, const HitArraysd& hits);
SPHRAY_API void occluded(const SphereBVHd& bvh, std::span<const Rayd> rays,
                         std::span<bool> blocked);

}  // namespace sphray
