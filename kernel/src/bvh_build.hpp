// The BVH builder and refit: plain C++ (and oneTBB when the build found it), the same for every
// instruction set; only the width W differs. See docs/bvh.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <vector>

#include "sphray/bvh.hpp"
#include "sphray/spheres.hpp"

namespace sphray::detail {

/// What a built tree owns; BvhData points into it.
struct BvhArrays {
  struct AlignedDelete {
    void operator()(float* p) const { ::operator delete[](p, std::align_val_t{64}); }
  };
  std::size_t width = 0;
  std::unique_ptr<float[], AlignedDelete> nodes;
  std::size_t node_count = 0;
  SphereSoA spheres;               // leaf order, padded to whole batches
  std::vector<std::uint32_t> ids;  // per sphere slot; kNoHit for padding
  std::size_t source_count = 0;    // the view's count

  BvhData data() const;
  std::size_t memory_bytes() const;
};

/// Child reference of a node slot that holds nothing (its box is empty).
inline constexpr std::uint32_t kBvhEmptySlot = 0x7fffffffu;

/// Builds the tree over spheres for nodes and leaves of width children / spheres, on at most
/// threads threads (0: all). Throws std::length_error past 2^31 spheres.
BvhArrays build_bvh(SphereView spheres, std::size_t width, unsigned threads);

/// Copies the moved spheres into the tree's leaf order and recomputes every box bottom-up.
void refit_bvh(BvhArrays& tree, SphereView spheres);

}  // namespace sphray::detail
