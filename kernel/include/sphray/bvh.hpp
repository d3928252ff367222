// SphereBVH: a wide bounding volume hierarchy over spheres, for scenes too large for brute force.
//
// Built once from a SphereView, it keeps its own copy of the spheres (in leaf order, with their
// original ids), so the view may change or go away afterwards. Queries follow the contract of
// query.hpp exactly: the same id and t as brute force on the same spheres with the same
// instruction set, ties to the lower id, the same handling of invalid rays and spheres.
//
//   sphray::SphereBVH bvh(spheres.view());
//   sphray::Hit hit = sphray::intersect(bvh, ray);
//   ...  // spheres moved, same count:
//   bvh.refit(spheres.view());
//
// A node holds as many children as one SIMD batch has lanes, and a leaf as many spheres: the
// tree is laid out for one instruction set, active_isa() unless another is given, and queried
// with that set's kernel. Queries are const and thread-safe; build and refit are not queries.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "sphray/isa.hpp"
#include "sphray/ray.hpp"
#include "sphray/spheres.hpp"

namespace sphray {

namespace detail {
/// The flat arrays a traversal reads (see docs/bvh.md, "Layout"). Not part of the stable API.
struct BvhData {
  /// Children per node and spheres per leaf batch.
  std::size_t width = 0;
  /// Node k starts at nodes + k * kBvhNodeRows * width: the children's boxes as six arrays of
  /// width floats (lo x, hi x, lo y, hi y, lo z, hi z), then width child references (uint32
  /// bits), so that every row is aligned to a batch. Node 0 is the root.
  const float* nodes = nullptr;
  std::size_t node_count = 0;
  /// The spheres in leaf order, each leaf an aligned batch of width slots: its spheres (at
  /// most width), then never-hit padding (radius 0). ids holds each slot's id in the view the
  /// tree was built from (kNoHit for padding).
  SphereView spheres{nullptr, nullptr, nullptr, nullptr, 0, 0};
  const std::uint32_t* ids = nullptr;
  /// The number of spheres the tree was built over.
  std::size_t count = 0;
  /// Bytes the nodes, spheres and ids take (SphereBVH::memory_bytes()).
  std::size_t memory_bytes = 0;
  /// How many leaf boxes a point of the tree's box lies in, on average (0: unknown). The
  /// traversal picks its leaf test by it.
  float leaf_overlap = 0.0f;
};

/// Trees whose leaf_overlap reaches this take the branch-free leaf test (bvh_traverse.hpp).
inline constexpr float kBvhBranchFreeOverlap = 1.5f;
/// Floats per child in a node: six box planes and the reference.
inline constexpr std::size_t kBvhNodeRows = 7;
/// A child reference with this bit set is a leaf: bits 0-30 hold its first slot, a multiple
/// of the width, plus its sphere count minus one (which is below the width). Otherwise it is a
/// node's index.
inline constexpr std::uint32_t kBvhLeafBit = 0x80000000u;
inline constexpr std::uint32_t kBvhLeafFirstMask = kBvhLeafBit - 1;
/// The deepest tree the builder makes (it switches to median splits to stay within it), which
/// bounds the traversal stack to kBvhMaxDepth * (width - 1) + 1 entries.
inline constexpr std::size_t kBvhMaxDepth = 64;
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

class SphereBVH {
 public:
  /// An empty tree (no spheres), for the active instruction set.
  SphereBVH();
  /// Builds over spheres for the active instruction set. Throws std::length_error when the
  /// tree's sphere slots would reach 2^31: each leaf takes a whole batch of W slots (W the
  /// instruction set's width, 16 for AVX-512) however few spheres it holds, so the limit is
  /// met before 2^31 spheres. Below 2^31 / W spheres (2^27 with AVX-512, 2^28 with AVX2) a
  /// build never meets it; above, it depends on how full the leaves come out.
  explicit SphereBVH(SphereView spheres, BvhBuildOptions options = {});
  /// Builds over spheres for isa. Throws std::invalid_argument if find_kernel(isa) is null or
  /// isa is not one of the Isa enumerators.
  SphereBVH(SphereView spheres, Isa isa, BvhBuildOptions options = {});

  /// A moved-from tree is the empty tree of the same instruction set: size() 0, every query a
  /// miss, refit() with an empty view only.
  SphereBVH(SphereBVH&&) noexcept;
  SphereBVH& operator=(SphereBVH&&) noexcept;
  ~SphereBVH();

  /// Takes the new centres and radii of the same spheres (same count, same ids) and updates the
  /// boxes, keeping the tree's shape: much cheaper than a rebuild, but the tree gets slower as
  /// spheres drift far from where they were built. Throws std::invalid_argument if the count
  /// differs.
  void refit(SphereView spheres);

  /// The number of spheres (the view's count at build time).
  std::size_t size() const;
  /// The instruction set the tree is laid out for and queried with.
  Isa isa() const;
  /// Bytes held: the sphere copy, the ids and the nodes. memory_bytes() / size() is the
  /// figure docs/bvh.md reports as bytes per sphere.
  std::size_t memory_bytes() const;

  /// The traversal's view of the tree (for the kernels and tests; not a stable API).
  const detail::BvhData& data() const { return data_; }
  const Kernel& kernel() const { return *kernel_; }

 private:
  void become_empty() noexcept;

  struct Storage;
  std::unique_ptr<Storage> storage_;  // null once moved from
  detail::BvhData data_;
  const Kernel* kernel_;
};

/// Closest hit of ray among the tree's spheres: the same result as intersect(view, ray) on the
/// spheres it was built (or last refitted) from.
Hit intersect(const SphereBVH& bvh, const Ray& ray);

/// True if any sphere is hit in (tmin, tmax).
bool occluded(const SphereBVH& bvh, const Ray& ray);

/// hits[i] = intersect(bvh, rays[i]). Throws std::length_error unless
/// hits.size() == rays.size().
void intersect(const SphereBVH& bvh, std::span<const Ray> rays, std::span<Hit> hits);

}  // namespace sphray
