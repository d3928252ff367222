#include "sphray/mpi/spatial_split.hpp"

#include <algorithm>
#include <stdexcept>

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

std::vector<std::vector<std::uint32_t>> spatial_shares(SphereView spheres, int ranks) {
  if (ranks < 1) throw std::invalid_argument("spatial_shares: expected ranks >= 1");
  const std::vector<std::uint32_t> order = morton_order(spheres);
  std::vector<std::vector<std::uint32_t>> shares;
  for (int r = 0; r < ranks; ++r)
    shares.push_back(run_of(order, r, ranks));
  return shares;
}

}  // namespace sphray::mpi
