// The layout of a SphereBVH node and of a child reference, as types (docs/bvh.md, "Layout"):
// the builder, refit and both walks read and write nodes through these only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "bvh/bvh_data.hpp"
#include "simd/isa_namespace.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

// What a child slot of a node holds: nothing, another node (its index), or a leaf: an aligned
// batch of width sphere slots whose first count (1 to width) hold spheres, the rest never-hit
// padding. A leaf keeps its first slot, a multiple of the width, plus count - 1 below the
// leaf bit, so that a node needs no row of counts.
class ChildRef {
 public:
  static constexpr std::uint32_t kEmptyBits = 0x7fffffffu;

  // Uninitialised, like the integer it is: a walk's stack holds these.
  ChildRef() = default;
  constexpr explicit ChildRef(std::uint32_t bits) : bits_(bits) {}
  static constexpr ChildRef empty() { return ChildRef(kEmptyBits); }
  static constexpr ChildRef node(std::size_t index) {
    return ChildRef(static_cast<std::uint32_t>(index));
  }
  static constexpr ChildRef leaf(std::size_t first, std::size_t count) {
    return ChildRef(kBvhLeafBit | static_cast<std::uint32_t>(first + count - 1));
  }

  constexpr bool is_empty() const { return bits_ == kEmptyBits; }
  constexpr bool is_leaf() const { return (bits_ & kBvhLeafBit) != 0; }
  constexpr std::size_t node_index() const { return bits_; }
  constexpr std::size_t first(std::size_t width) const {
    return bits_ & kBvhLeafFirstMask & ~static_cast<std::uint32_t>(width - 1);
  }
  constexpr std::size_t count(std::size_t width) const {
    return (bits_ & static_cast<std::uint32_t>(width - 1)) + 1;
  }
  constexpr std::uint32_t bits() const { return bits_; }

 private:
  std::uint32_t bits_;
};

// Node index of a tree of width children: kBvhNodeRows rows of width floats, each on a batch
// boundary: the children's boxes as six rows (lo x, hi x, lo y, hi y, lo z, hi z), then their
// references' bits. Float is float to write a node (builder, refit), const float to read it.
template <class Float>
class NodeView {
 public:
  NodeView(Float* nodes, std::size_t index, std::size_t width)
      : rows_(nodes + index * kBvhNodeRows * width), width_(width) {}

  // Row 2 axis + side of the box planes, side 0 for lo and 1 for hi: what a SIMD walk loads.
  Float* plane_row(std::size_t row) const { return rows_ + row * width_; }
  Float& lo(int axis, std::size_t k) const { return plane_row(2 * axis)[k]; }
  Float& hi(int axis, std::size_t k) const { return plane_row(2 * axis + 1)[k]; }

  ChildRef ref(std::size_t k) const {
    return ChildRef(__builtin_bit_cast(std::uint32_t, rows_[6 * width_ + k]));
  }
  void set_ref(std::size_t k, ChildRef ref) const requires(!std::is_const_v<Float>) {
    rows_[6 * width_ + k] = __builtin_bit_cast(float, ref.bits());
  }

 private:
  Float* rows_;
  std::size_t width_;
};

// Floats a tree of node_count nodes of width children takes.
constexpr std::size_t node_floats(std::size_t node_count, std::size_t width) {
  return node_count * kBvhNodeRows * width;
}

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
