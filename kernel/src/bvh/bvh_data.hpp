// The flat arrays a SphereBVH's walks read, and the library's access to them. Internal: the
// public header (sphray/bvh.hpp) holds only the API.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sphray/bvh.hpp"
#include "sphray/spheres.hpp"

namespace sphray::detail {

/// The flat arrays a traversal reads (see docs/bvh.md, "Layout"), for spheres of scalar S. The
/// boxes are float whatever S: a double tree's are rounded outward (docs/double.md).
template <Scalar S>
struct BasicBvhData {
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
  BasicSphereView<S> spheres{nullptr, nullptr, nullptr, nullptr, 0, 0};
  const std::uint32_t* ids = nullptr;
  /// Built flat: slot i holds sphere i, in full leaves under the root, so that brute force on
  /// spheres (its count set to count) is the tree's answer (kBvhBruteForceLeaves).
  bool flat = false;
  /// The number of spheres the tree was built over.
  std::size_t count = 0;
  /// Bytes the nodes, spheres and ids take (SphereBVH::memory_bytes()).
  std::size_t memory_bytes = 0;
  /// How many leaf boxes a point of the tree's box lies in, on average (0: unknown). The
  /// traversal picks its leaf test by it.
  float leaf_overlap = 0.0f;
};

using BvhData = BasicBvhData<float>;
using BvhDatad = BasicBvhData<double>;

/// Trees whose leaf_overlap reaches this take the branch-free leaf test (bvh/leaf_test.hpp;
/// why 1.25: QueryPlan::branch_free_leaves).
inline constexpr float kBvhBranchFreeOverlap = 1.25f;
/// A tree of at most this many leaves (of full width) is built flat and answers by brute force
/// (QueryPlan::brute_force_tree).
inline constexpr std::size_t kBvhBruteForceLeaves = 8;
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

struct EntryTable;

/// What the library (and its tests) see of a SphereBVH: its arrays and its kernel. A moved-from
/// tree reads as the empty tree, which every query misses.
struct BvhAccess {
  static const BvhData& data(const SphereBVH& bvh);
  static const BvhDatad& data(const SphereBVHd& bvh);
  template <Scalar S>
  static const EntryTable& entries(const BasicSphereBVH<S>& bvh) {
    return *bvh.entries_;
  }
};

}  // namespace sphray::detail
