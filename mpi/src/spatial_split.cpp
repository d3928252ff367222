#include "sphray/mpi/spatial_split.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sphray::mpi {
namespace {

// The bits of a 21-bit integer spread to every third bit of a 63-bit one.
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

bool finite(Vec3 c) {
  return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
}

struct Box {
  Vec3 lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
          std::numeric_limits<float>::max()};
  Vec3 hi{-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
          -std::numeric_limits<float>::max()};
};

// The cell, 0 to 2^21 - 1, of coordinate v in [lo, hi] (in double: no overflow for any floats).
std::uint64_t cell(float v, float lo, float hi) {
  const double extent = static_cast<double>(hi) - static_cast<double>(lo);
  if (!(extent > 0.0)) return 0;
  const double unit = (static_cast<double>(v) - static_cast<double>(lo)) / extent;
  return static_cast<std::uint64_t>(std::clamp(unit, 0.0, 1.0) * 2097151.0);
}

}  // namespace

std::vector<std::uint32_t> morton_order(SphereView spheres) {
  const auto center = [&](std::size_t i) {
    return Vec3{spheres.cx[i], spheres.cy[i], spheres.cz[i]};
  };
  Box box;
  for (std::size_t i = 0; i < spheres.count; ++i) {
    const Vec3 c = center(i);
    if (!finite(c)) continue;
    box.lo = {std::min(box.lo.x, c.x), std::min(box.lo.y, c.y), std::min(box.lo.z, c.z)};
    box.hi = {std::max(box.hi.x, c.x), std::max(box.hi.y, c.y), std::max(box.hi.z, c.z)};
  }
  // (Morton code, id): sorting the pairs orders by place, ties by id, the same on every rank.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(spheres.count);
  for (std::size_t i = 0; i < spheres.count; ++i) {
    const Vec3 c = center(i);
    const std::uint64_t code = finite(c) ? spread_bits(cell(c.x, box.lo.x, box.hi.x)) |
                                               spread_bits(cell(c.y, box.lo.y, box.hi.y)) << 1 |
                                               spread_bits(cell(c.z, box.lo.z, box.hi.z)) << 2
                                         : 0;
    keys[i] = {code, static_cast<std::uint32_t>(i)};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint32_t> order(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k)
    order[k] = keys[k].second;
  return order;
}

std::vector<std::uint32_t> spatial_share(SphereView spheres, int rank, int ranks) {
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw std::invalid_argument("spatial_share: expected 0 <= rank < ranks");
  const std::vector<std::uint32_t> order = morton_order(spheres);
  const std::size_t n = order.size(), r = static_cast<std::size_t>(rank),
                    p = static_cast<std::size_t>(ranks);
  std::vector<std::uint32_t> ids(order.begin() + static_cast<std::ptrdiff_t>(n * r / p),
                                 order.begin() + static_cast<std::ptrdiff_t>(n * (r + 1) / p));
  std::sort(ids.begin(), ids.end());
  return ids;
}

}  // namespace sphray::mpi
