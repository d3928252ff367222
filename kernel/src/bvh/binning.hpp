// The binned SAH's bookkeeping: how centres map to bins, a range of prims with its boxes, a
// bin, and a chosen split (Wald, "On fast Construction of SAH-based Bounding Volume
// Hierarchies", IEEE RT 2007).
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "bvh/prim.hpp"

namespace sphray::detail {

// How a range's centres map to bins: (centre - origin) * scale, per axis, clamped to
// [0, last]. An axis with scale 0 is not binned (all its centres are equal).
struct Binning {
  Lanes origin, scale, last;

  // The bin of centre c on every axis; NaN (0 * inf) goes to bin 0. The builder computes every
  // bin index here, so binning and partition agree bit for bit.
  LaneInts bins(const Lanes& c) const {
    const Lanes zero(0.0f);
    const Lanes b = (c - origin) * scale;
    return xsimd::to_int(xsimd::min(xsimd::select(b > zero, b, zero), last));
  }
};

// A range of the prims that will become one child of a node.
struct Cluster {
  std::size_t begin, end;
  Box box;       // of the spheres
  Box centroid;  // of their centres

  std::size_t size() const { return end - begin; }
};

struct Bin {
  Box box;
  std::size_t count = 0;

  void grow(const Bin& b) {
    box.grow(b.box);
    count += b.count;
  }
};

struct Split {
  int axis = -1;
  std::int32_t bin = 0;  // spheres in bins <= bin go left
  Binning binning;
  Bin left, right;       // what each side will hold, or of the sample binned
  bool sampled = false;  // whether the bins saw only a sample of the range
};

}  // namespace sphray::detail
