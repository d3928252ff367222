// The BVH builder and refit: plain C++ (and oneTBB when the build found it), the same for every
// instruction set; only the width W differs. See docs/bvh.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>

#include "bvh/bvh_data.hpp"
#include "sphray/spheres.hpp"

namespace sphray::detail {

template <class T>
struct AlignedDelete {
  void operator()(T* p) const { ::operator delete[](p, std::align_val_t{64}); }
};
/// An array on a 64-byte boundary.
template <class T>
using AlignedArray = std::unique_ptr<T[], AlignedDelete<T>>;

/// What a built tree over spheres of scalar S owns; BasicBvhData<S> points into it. The nodes
/// are float whatever S (bvh_data.hpp).
template <Scalar S>
struct BasicBvhArrays {
  std::size_t width = 0;
  AlignedArray<float> nodes;
  std::size_t node_count = 0;
  /// Four arrays of slots scalars (cx, cy, cz, radius): the spheres in leaf order, then width
  /// never-hit spheres that a read of the last leaf's whole batch may reach.
  AlignedArray<S> spheres;
  AlignedArray<std::uint32_t> ids;  // per slot; kNoHit for the padding
  /// Per slot, the mask of its sphere (0 for the padding); null when the view had no masks.
  AlignedArray<std::uint32_t> masks;
  std::size_t slots = 0;
  bool flat = false;             // see BvhData::flat
  std::size_t source_count = 0;  // the view's count
  /// The sum of the leaf boxes' volumes over the root box's: how many leaf boxes a point of
  /// the root box lies in, on average. 0 when that is unknown (no leaves, or unbounded boxes).
  float leaf_overlap = 0.0f;

  BasicBvhData<S> data() const;
  std::size_t memory_bytes() const;
};

using BvhArrays = BasicBvhArrays<float>;

/// Builds the tree over spheres for nodes of width children and leaves of at most width
/// spheres. Throws std::length_error past 2^31 spheres.
template <Scalar S>
BasicBvhArrays<S> build_bvh(BasicSphereView<S> spheres, std::size_t width,
                            const BvhBuildOptions& options, const BuildProgress& progress);

/// Copies the moved spheres into the tree's leaf order and recomputes every box bottom-up.
template <Scalar S>
void refit_bvh(BasicBvhArrays<S>& tree, BasicSphereView<S> spheres);

/// Gives tree the masks of spheres slot by slot (the view's ids), or none if it has none.
template <Scalar S>
void copy_masks(BasicBvhArrays<S>& tree, BasicSphereView<S> spheres);

/// The leaf boxes' summed volume over the root box's (BasicBvhArrays::leaf_overlap), from the
/// written nodes.
template <Scalar S>
float measure_leaf_overlap(const BasicBvhArrays<S>& tree);

}  // namespace sphray::detail
