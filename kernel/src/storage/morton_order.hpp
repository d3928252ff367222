// Points in Morton (Z-order) along a curve through the box around them: neighbours in the order
// are near in space, which the callers use to keep work local (MPI's split of the spheres
// between ranks, Python's batch queries walking the same tree nodes one after another). A
// header of templates, for the sphray_kernel_internals target's users.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "sphray/vec3.hpp"

namespace sphray::detail {

/// The bits of a 21-bit integer spread to every third bit of a 63-bit one.
constexpr std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

/// The cell, 0 to 2^21 - 1, of coordinate v in [lo, hi] (in double: no overflow for any floats).
inline std::uint64_t morton_cell(float v, float lo, float hi) {
  const double extent = static_cast<double>(hi) - static_cast<double>(lo);
  if (!(extent > 0.0)) return 0;
  const double unit = (static_cast<double>(v) - static_cast<double>(lo)) / extent;
  return static_cast<std::uint64_t>(std::clamp(unit, 0.0, 1.0) * 2097151.0);
}

/// A sort of (code, index) pairs: std::sort unless the caller has a parallel one.
struct SerialSort {
  template <class It>
  void operator()(It begin, It end) const {
    std::sort(begin, end);
  }
};

/// The indices 0 to n - 1 of the points centre(i) -> Vec3, ordered along the Morton curve
/// through the box around the finite ones, ties by index; points with a NaN or infinite
/// coordinate first. sort(begin, end) sorts a vector of (code, index) pairs ascending. The
/// order depends on the points alone (MPI ranks rely on computing the same one).
template <class Centre, class Sort = SerialSort>
std::vector<std::uint32_t> morton_order(std::size_t n, const Centre& centre, Sort sort = {}) {
  const auto finite = [](Vec3 c) {
    return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
  };
  constexpr float kMax = std::numeric_limits<float>::max();
  Vec3 lo{kMax, kMax, kMax}, hi{-kMax, -kMax, -kMax};
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 c = centre(i);
    if (!finite(c)) continue;
    lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
    hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 c = centre(i);
    const std::uint64_t code = finite(c) ? spread_bits(morton_cell(c.x, lo.x, hi.x)) |
                                               spread_bits(morton_cell(c.y, lo.y, hi.y)) << 1 |
                                               spread_bits(morton_cell(c.z, lo.z, hi.z)) << 2
                                         : 0;
    keys[i] = {code, static_cast<std::uint32_t>(i)};
  }
  sort(keys.begin(), keys.end());
  std::vector<std::uint32_t> order(n);
  for (std::size_t k = 0; k < n; ++k)
    order[k] = keys[k].second;
  return order;
}

}  // namespace sphray::detail
