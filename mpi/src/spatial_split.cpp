#include "sphray/mpi/spatial_split.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "storage/morton_order.hpp"

namespace sphray::mpi {

std::vector<std::uint32_t> morton_order(SphereView spheres) {
  return detail::morton_order(spheres.count, [&](std::size_t i) {
    return Vec3{spheres.cx[i], spheres.cy[i], spheres.cz[i]};
  });
}

namespace {

// Rank r's run of the Morton order, ascending.
std::vector<std::uint32_t> run_of(const std::vector<std::uint32_t>& order, int rank, int ranks) {
  const std::size_t n = order.size(), r = static_cast<std::size_t>(rank),
                    p = static_cast<std::size_t>(ranks);
  std::vector<std::uint32_t> ids(order.begin() + static_cast<std::ptrdiff_t>(n * r / p),
                                 order.begin() + static_cast<std::ptrdiff_t>(n * (r + 1) / p));
  std::sort(ids.begin(), ids.end());
  return ids;
}

}  // namespace

std::vector<std::uint32_t> spatial_share(SphereView spheres, int rank, int ranks) {
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw std::invalid_argument("spatial_share: expected 0 <= rank < ranks");
  return run_of(morton_order(spheres), rank, ranks);
}

namespace {

// Splits ids[begin, end) between ranks [first, first + count): the ranks below count / 2 get
// the spheres below the cut along the longest axis of their centres' box, in proportion.
void split_by_planes(SphereView spheres, Vec3 weights, std::vector<std::uint32_t>& ids,
                     std::size_t begin, std::size_t end, int first, int count, int only,
                     std::vector<std::vector<std::uint32_t>>& shares) {
  if (count == 1) {
    shares[static_cast<std::size_t>(first)].assign(ids.begin() + static_cast<std::ptrdiff_t>(begin),
                                                   ids.begin() + static_cast<std::ptrdiff_t>(end));
    std::sort(shares[static_cast<std::size_t>(first)].begin(),
              shares[static_cast<std::size_t>(first)].end());
    return;
  }
  const float* axes[3] = {spheres.cx, spheres.cy, spheres.cz};
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i = begin; i < end; ++i)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], axes[k][ids[i]]);
      hi[k] = std::max(hi[k], axes[k][ids[i]]);
    }
  const float weight[3] = {weights.x, weights.y, weights.z};
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if ((hi[k] - lo[k]) * weight[k] > (hi[axis] - lo[axis]) * weight[axis]) axis = k;
  const int left = count / 2;
  const std::size_t cut =
      begin + (end - begin) * static_cast<std::size_t>(left) / static_cast<std::size_t>(count);
  const float* along = axes[axis];
  std::nth_element(ids.begin() + static_cast<std::ptrdiff_t>(begin),
                   ids.begin() + static_cast<std::ptrdiff_t>(cut),
                   ids.begin() + static_cast<std::ptrdiff_t>(end),
                   [along](std::uint32_t a, std::uint32_t b) {
                     return along[a] < along[b] || (along[a] == along[b] && a < b);
                   });
  // only >= 0: the share of that rank alone, so the other side is never split further.
  if (only < 0 || only < first + left)
    split_by_planes(spheres, weights, ids, begin, cut, first, left, only, shares);
  if (only < 0 || only >= first + left)
    split_by_planes(spheres, weights, ids, cut, end, first + left, count - left, only, shares);
}

// The shares of every rank (only < 0) or of rank `only` alone (the others left empty).
std::vector<std::vector<std::uint32_t>> split_shares(SphereView spheres, Vec3 weights, int ranks,
                                                     int only) {
  // Spheres with a NaN or infinite centre go with rank 0, as in spatial_share.
  std::vector<std::uint32_t> finite, other;
  for (std::size_t i = 0; i < spheres.count; ++i) {
    const bool ok = std::isfinite(spheres.cx[i]) && std::isfinite(spheres.cy[i]) &&
                    std::isfinite(spheres.cz[i]);
    (ok ? finite : other).push_back(static_cast<std::uint32_t>(i));
  }
  std::vector<std::vector<std::uint32_t>> shares(static_cast<std::size_t>(ranks));
  split_by_planes(spheres, weights, finite, 0, finite.size(), 0, ranks, only, shares);
  if (only <= 0) {
    shares[0].insert(shares[0].end(), other.begin(), other.end());
    std::sort(shares[0].begin(), shares[0].end());
  }
  return shares;
}

}  // namespace

std::vector<std::vector<std::uint32_t>> plane_shares(SphereView spheres, int ranks, Vec3 weights) {
  if (ranks < 1) throw std::invalid_argument("plane_shares: expected ranks >= 1");
  return split_shares(spheres, weights, ranks, -1);
}

std::vector<std::uint32_t> plane_share(SphereView spheres, int rank, int ranks, Vec3 weights) {
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw std::invalid_argument("plane_share: expected 0 <= rank < ranks");
  return std::move(split_shares(spheres, weights, ranks, rank)[static_cast<std::size_t>(rank)]);
}

std::vector<std::vector<std::uint32_t>> spatial_shares(SphereView spheres, int ranks) {
  if (ranks < 1) throw std::invalid_argument("spatial_shares: expected ranks >= 1");
  const std::vector<std::uint32_t> order = morton_order(spheres);
  std::vector<std::vector<std::uint32_t>> shares;
  for (int r = 0; r < ranks; ++r)
    shares.push_back(run_of(order, r, ranks));
  return shares;
}

}  // namespace sphray::mpi
