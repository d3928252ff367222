#include "sphray/mpi/spatial_split.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

#include "sphray/mpi/regions.hpp"
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

// A slab of a cell along its cut's axis: its spheres' count and the box around those that can
// be hit.
struct Slab {
  std::size_t count = 0;
  RegionBox box{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}, true};

  void add(const Slab& other) {
    count += other.count;
    for (int k = 0; k < 3; ++k) {
      box.lo[k] = std::min(box.lo[k], other.box.lo[k]);
      box.hi[k] = std::max(box.hi[k], other.box.hi[k]);
    }
    box.empty = box.empty && other.box.empty;
  }
};

// Slabs a cell is binned into to place a cut by its rays: the cut lies on a boundary between
// two, within 1/1024 of the cell's extent.
constexpr std::size_t kCutSlabs = 1024;

// Cuts ids[begin, end) where the probes divide rather than the spheres: of the probes that enter
// either side's box, the fraction `share` enters the lower side's first (in a dense cloud a ray
// mostly ends in the first region it enters). One pass bins the spheres into slabs of equal
// width along the axis, each with its count and box; a bisection over the slab boundaries that
// leave each side between a quarter and three quarters of the spheres (for their memory) then
// tests the probes against the two sides' boxes, joined from the slabs. The spheres below the
// boundary go first; returns where they end, or nothing when the probes cannot place the cut
// (a few spheres, centres that do not spread along the axis, no boundary keeps the quarters, or no
// probe enters either side), for the cut by count.
std::optional<std::size_t> cut_by_probes(SphereView spheres, const float* along, float lo, float hi,
                                         std::vector<std::uint32_t>& ids, std::size_t begin,
                                         std::size_t end, double share,
                                         std::span<const Ray> probes) {
  const std::size_t n = end - begin;
  if (!(lo < hi) || n < 8) return std::nullopt;
  const float width = (hi - lo) / static_cast<float>(kCutSlabs);
  if (!(width > 0) || !std::isfinite(width)) return std::nullopt;  // too narrow or too wide
  const auto slab_of = [&](std::uint32_t id) {
    const float at = (along[id] - lo) / width;  // in [0, kCutSlabs]: finite centres only
    return at > 0 ? std::min(kCutSlabs - 1, static_cast<std::size_t>(at)) : std::size_t{0};
  };
  std::vector<Slab> slabs(kCutSlabs);
  for (std::size_t i = begin; i < end; ++i) {
    Slab& slab = slabs[slab_of(ids[i])];
    ++slab.count;
    const Vec3 c = {spheres.cx[ids[i]], spheres.cy[ids[i]], spheres.cz[ids[i]]};
    const float r = spheres.radius[ids[i]];
    if (!(r > 0) || !std::isfinite(r)) continue;  // never hit: no part of a region
    const float centre[3] = {c.x, c.y, c.z};
    for (int k = 0; k < 3; ++k) {
      slab.box.lo[k] = std::min(slab.box.lo[k], centre[k] - r);
      slab.box.hi[k] = std::max(slab.box.hi[k], centre[k] + r);
    }
    slab.box.empty = false;
  }
  // below[j]: the slabs under boundary j joined; above[j]: those from it on.
  std::vector<Slab> below(kCutSlabs + 1), above(kCutSlabs + 1);
  for (std::size_t j = 0; j < kCutSlabs; ++j) {
    below[j + 1] = below[j];
    below[j + 1].add(slabs[j]);
    above[kCutSlabs - j - 1] = above[kCutSlabs - j];
    above[kCutSlabs - j - 1].add(slabs[kCutSlabs - j - 1]);
  }
  std::size_t low = 1;
  while (low < kCutSlabs && below[low].count < n / 4)
    ++low;
  std::size_t high = low;
  while (high + 1 < kCutSlabs && below[high + 1].count <= n - n / 4)
    ++high;
  if (below[low].count < n / 4 || below[high].count > n - n / 4) return std::nullopt;
  // The fraction of the probes entering either side that enter the lower side first.
  const auto lower_first = [&](std::size_t j) -> std::optional<double> {
    const RegionBox sides[2] = {below[j].box, above[j].box};
    double lower = 0, either = 0;
    for (const Ray& probe : probes) {
      const RegionKey first = next_region(sides, probe, probe.tmax, RegionKey{});
      if (first.region < 0) continue;
      either += 1;
      lower += first.region == 0 ? 1 : 0;
    }
    if (either == 0) return std::nullopt;
    return lower / either;
  };
  if (!lower_first(low + (high - low) / 2)) return std::nullopt;
  // The least boundary whose lower side takes the share (the fraction grows with the boundary).
  while (low < high) {
    const std::size_t j = low + (high - low) / 2;
    if (lower_first(j).value_or(1.0) >= share)
      high = j;
    else
      low = j + 1;
  }
  const auto cut = std::partition(ids.begin() + static_cast<std::ptrdiff_t>(begin),
                                  ids.begin() + static_cast<std::ptrdiff_t>(end),
                                  [&](std::uint32_t id) { return slab_of(id) < low; });
  return static_cast<std::size_t>(cut - ids.begin());
}

// Splits ids[begin, end) between ranks [first, first + count): the ranks below count / 2 get
// the spheres below the cut along the longest axis of their centres' box, in proportion (of
// the spheres, or of the probes when there are any).
void split_by_planes(SphereView spheres, Vec3 weights, std::span<const Ray> probes,
                     std::vector<std::uint32_t>& ids, std::size_t begin, std::size_t end, int first,
                     int count, int only, std::vector<std::vector<std::uint32_t>>& shares) {
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
  std::size_t cut =
      begin + (end - begin) * static_cast<std::size_t>(left) / static_cast<std::size_t>(count);
  const float* along = axes[axis];
  const std::optional<std::size_t> by_probes =
      probes.empty() ? std::nullopt
                     : cut_by_probes(spheres, along, lo[axis], hi[axis], ids, begin, end,
                                     static_cast<double>(left) / count, probes);
  if (by_probes) {
    cut = *by_probes;
  } else {
    std::nth_element(ids.begin() + static_cast<std::ptrdiff_t>(begin),
                     ids.begin() + static_cast<std::ptrdiff_t>(cut),
                     ids.begin() + static_cast<std::ptrdiff_t>(end),
                     [along](std::uint32_t a, std::uint32_t b) {
                       return along[a] < along[b] || (along[a] == along[b] && a < b);
                     });
  }
  // only >= 0: the share of that rank alone, so the other side is never split further.
  if (only < 0 || only < first + left)
    split_by_planes(spheres, weights, probes, ids, begin, cut, first, left, only, shares);
  if (only < 0 || only >= first + left)
    split_by_planes(spheres, weights, probes, ids, cut, end, first + left, count - left, only,
                    shares);
}

// The shares of every rank (only < 0) or of rank `only` alone (the others left empty).
std::vector<std::vector<std::uint32_t>> split_shares(SphereView spheres, Vec3 weights,
                                                     std::span<const Ray> probes, int ranks,
                                                     int only) {
  // Spheres with a NaN or infinite centre go with rank 0, as in spatial_share.
  std::vector<std::uint32_t> finite, other;
  for (std::size_t i = 0; i < spheres.count; ++i) {
    const bool ok = std::isfinite(spheres.cx[i]) && std::isfinite(spheres.cy[i]) &&
                    std::isfinite(spheres.cz[i]);
    (ok ? finite : other).push_back(static_cast<std::uint32_t>(i));
  }
  std::vector<std::vector<std::uint32_t>> shares(static_cast<std::size_t>(ranks));
  split_by_planes(spheres, weights, probes, finite, 0, finite.size(), 0, ranks, only, shares);
  if (only <= 0) {
    shares[0].insert(shares[0].end(), other.begin(), other.end());
    std::sort(shares[0].begin(), shares[0].end());
  }
  return shares;
}

}  // namespace

std::vector<std::vector<std::uint32_t>> plane_shares(SphereView spheres, int ranks, Vec3 weights,
                                                     std::span<const Ray> probes) {
  if (ranks < 1) throw std::invalid_argument("plane_shares: expected ranks >= 1");
  return split_shares(spheres, weights, probes, ranks, -1);
}

std::vector<std::uint32_t> plane_share(SphereView spheres, int rank, int ranks, Vec3 weights,
                                       std::span<const Ray> probes) {
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw std::invalid_argument("plane_share: expected 0 <= rank < ranks");
  return std::move(
      split_shares(spheres, weights, probes, ranks, rank)[static_cast<std::size_t>(rank)]);
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
