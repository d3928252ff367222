// What the builder and refit work on: four-lane boxes, the builder's view of a sphere (Prim)
// and a child's box in a node. Plain C++ over xsimd's baseline architecture; the builder is
// the same for every instruction set.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>

#include <xsimd/xsimd.hpp>

#include "brute/validity.hpp"
#include "bvh/node.hpp"
#include "storage/huge_pages.hpp"

namespace sphray::detail {

using SPHRAY_ISA_NAMESPACE::ChildRef;
using SPHRAY_ISA_NAMESPACE::node_floats;
using SPHRAY_ISA_NAMESPACE::NodeView;

constexpr float kInf = INFINITY;
// Spheres per block of the parallel partition, at most. Fixed for given options, so that the
// blocks, and with them the order the partition leaves, do not depend on the thread count.
constexpr std::size_t kBlock = 4096;

// Four floats, x, y, z and a spare lane, in one SIMD register: xsimd's baseline architecture
// (SSE2 on x86-64, NEON on AArch64) is 4 wide. The builder needs nothing wider: it is bound by
// memory, not arithmetic.
using Lanes = xsimd::batch<float, xsimd::default_arch>;
using LaneInts = xsimd::batch<std::int32_t, xsimd::default_arch>;
static_assert(Lanes::size == 4, "the builder's boxes are four lanes");

// A box with a spare lane per corner, so that growing it is one min and one max.
struct alignas(16) Box {
  float lo[4] = {kInf, kInf, kInf, kInf};
  float hi[4] = {-kInf, -kInf, -kInf, -kInf};

  void grow(const Lanes& l, const Lanes& h) {
    xsimd::min(Lanes::load_aligned(lo), l).store_aligned(lo);
    xsimd::max(Lanes::load_aligned(hi), h).store_aligned(hi);
  }
  void grow(const Box& b) { grow(Lanes::load_aligned(b.lo), Lanes::load_aligned(b.hi)); }
  void grow(const Lanes& point) { grow(point, point); }
  bool empty() const { return !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]); }
  // Half the surface area; the SAH only compares ratios. Infinite for unbounded boxes.
  float half_area() const {
    if (empty()) return 0.0f;
    const float x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
    const float a = x * y + y * z + z * x;
    return std::isnan(a) ? kInf : a;
  }
  // In double, so that boxes up to 10^100 wide keep a finite volume. Infinite for unbounded
  // boxes.
  double volume() const {
    if (empty()) return 0.0;
    const double v = (double{hi[0]} - lo[0]) * (double{hi[1]} - lo[1]) * (double{hi[2]} - lo[2]);
    return std::isnan(v) ? HUGE_VAL : v;
  }
};

// A box in registers, grown only in the lanes a mask selects: a partition's side, grown
// without a branch.
using LaneMask = xsimd::batch_bool<float, xsimd::default_arch>;
struct BoxLanes {
  Lanes lo = Lanes(kInf), hi = Lanes(-kInf);

  void grow_if(const LaneMask& mask, const Lanes& l, const Lanes& h) {
    lo = xsimd::select(mask, xsimd::min(lo, l), lo);
    hi = xsimd::select(mask, xsimd::max(hi, h), hi);
  }
  // Grows box by this.
  void grow(Box& box) const { box.grow(lo, hi); }
};

// Half the side of a sphere's box on one axis: the radius, widened by 2^-20 of the
// coordinate's magnitude. That is more than the rounding of c -+ e, and enough to hold a grazing
// hit that the kernel's own rounding puts just outside the exact sphere. Per lane: r holds the
// radius in every lane.
// The widening is at least float's smallest step, 2^-149: a double sphere can be so small and
// so near the origin (|c| + r below 2^-130) that 2^-20 of it rounds to nothing in float, while
// double's rounding still puts a grazing hit outside the exact sphere, by far less than 2^-149.
// A float sphere is never that small (its radius is at least 2^-63), and there the floor is
// below half an ulp of the sum: float trees come out bit for bit as without it.
inline Lanes half_extent(const Lanes& c, const Lanes& r) {
  constexpr float kSmallestStep = 0x1p-149f;
  return r + ((xsimd::abs(c) + r) * Lanes(0x1p-20f) + Lanes(kSmallestStep));
}

// One sphere as the builder sees it, 16 bytes: its centre and radius, one aligned load. The
// build moves these records and nothing else but their ids (Prims), so every pass over a range
// reads memory in order, and the leaves' spheres are copied out of them in order at the end.
// The box's half extents are not stored but computed when needed (half_extent()): four SIMD
// operations cost less than 16 more bytes a sphere to hold and move, in a build bound by memory
// whose peak is the library's (issue 34: 10^8 spheres on 24 GB). An invalid sphere (never hit) has
// centre 0 and radius -inf: its half extents come out -inf, so its box c -+ e is empty and never
// widens a parent, and its centre still compares with the others.
struct alignas(16) Prim {
  float sphere[4];  // centre x, y, z; radius

  static Prim make(float x, float y, float z, float r) {
    if (!valid_sphere({x, y, z}, r)) return {{0.0f, 0.0f, 0.0f, -kInf}};
    return {{x, y, z, r}};
  }
  // A double sphere as a float record whose sphere holds it, so that the box the builder gives
  // the record holds the double sphere (a double tree's boxes are float, docs/double.md): the
  // centre rounded to the nearest float, the radius grown by how far that moved it (the sum of
  // the three moves bounds the distance) and rounded up. The rounding of that sum in double is
  // far below the box's own widening (half_extent). A centre beyond float's range is clamped
  // to it with an infinite radius: an unbounded box, which every ray enters.
  static Prim make(double x, double y, double z, double r) {
    if (!valid_sphere<double>({x, y, z}, r)) return {{0.0f, 0.0f, 0.0f, -kInf}};
    constexpr double kMax = 0x1.fffffep127;  // FLT_MAX
    const double c[3] = {x, y, z};
    Prim p;
    double moved = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
      const double clamped = c[axis] < -kMax ? -kMax : (c[axis] > kMax ? kMax : c[axis]);
      p.sphere[axis] = static_cast<float>(clamped);
      moved += __builtin_fabs(c[axis] - static_cast<double>(p.sphere[axis]));
    }
    const double grown = r + moved;
    float rf = static_cast<float>(grown);  // inf past float's range
    if (static_cast<double>(rf) < grown) rf = std::nextafter(rf, kInf);
    p.sphere[3] = rf;
    return p;
  }
  // The centre in lanes 0-2 (lane 3: the radius, which binning multiplies by 0).
  Lanes centre() const { return Lanes::load_aligned(sphere); }
  // The sphere's box, lo and hi, in lanes 0-2 (lane 3 is not used).
  std::pair<Lanes, Lanes> bounds() const {
    const Lanes c = centre(), r(sphere[3]);
    const Lanes e = half_extent(c, r);
    return {c - e, c + e};
  }
  // Grows box by the sphere's box.
  void grow(Box& box) const {
    const auto [lo, hi] = bounds();
    box.grow(lo, hi);
  }
};
static_assert(std::is_trivially_default_constructible_v<Prim> && sizeof(Prim) == 16);

// The builder's spheres and their ids (indices in the view), permuted together. The ids are an
// array of their own so that a prim stays 16 bytes, one aligned load. Default-initialised: the
// builder writes every element before reading it.
struct Prims {
  explicit Prims(std::size_t n) : data(new Prim[n]), ids(new std::uint32_t[n]), size(n) {
    prefer_huge_pages(data.get(), n * sizeof(Prim));
    prefer_huge_pages(ids.get(), n * sizeof(std::uint32_t));
  }
  Prim& operator[](std::size_t i) { return data[i]; }
  const Prim& operator[](std::size_t i) const { return data[i]; }
  // Swaps elements a and b (which may be the same), prim and id.
  void swap(std::size_t a, std::size_t b) {
    std::swap(data[a], data[b]);
    std::swap(ids[a], ids[b]);
  }
  std::unique_ptr<Prim[]> data;
  std::unique_ptr<std::uint32_t[]> ids;
  std::size_t size;
};

// The box refit gives a sphere: the same arithmetic as the build's.
template <class S>
Box sphere_box(S x, S y, S z, S r) {
  Box b;
  Prim::make(x, y, z, r).grow(b);
  return b;
}

// A child's box in a node, and back.
inline void write_box(const NodeView<float>& node, std::size_t k, const Box& b) {
  for (int axis = 0; axis < 3; ++axis) {
    node.lo(axis, k) = b.lo[axis];
    node.hi(axis, k) = b.hi[axis];
  }
}

inline Box read_box(const NodeView<const float>& node, std::size_t k) {
  Box b;
  for (int axis = 0; axis < 3; ++axis) {
    b.lo[axis] = node.lo(axis, k);
    b.hi[axis] = node.hi(axis, k);
  }
  return b;
}

}  // namespace sphray::detail
