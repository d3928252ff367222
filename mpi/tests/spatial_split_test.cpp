// spatial_share: every sphere goes to exactly one rank, in runs of equal size, and the ranks own
// compact regions: their boxes together are well below the ranks' count times the scene's (a
// split by id gives every rank nearly the whole scene's box).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sphray/mpi/spatial_split.hpp"

namespace {

// The volume of the box around the finite centres of ids; counts each id in owners.
double centres_box_volume(const sphray::SphereSoA& spheres, const std::vector<std::uint32_t>& ids,
                          std::vector<int>& owners) {
  sphray::Vec3 lo{1e9f, 1e9f, 1e9f}, hi{-1e9f, -1e9f, -1e9f};
  for (std::uint32_t id : ids) {
    ++owners[id];
    const sphray::Vec3 c = spheres.center(id);
    if (!std::isfinite(c.x)) continue;
    lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
    hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
  }
  return static_cast<double>(hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z);
}

TEST(MpiSpatialSplit, EverySphereHasOneRankAndRanksOwnCompactRegions) {
  std::mt19937 rng(3);
  sphray::SphereSoA spheres;
  for (int i = 0; i < 4000; ++i) {
    const auto coordinate = [&] { return static_cast<float>(rng() % 1000) * 0.01f; };
    spheres.add({coordinate(), coordinate(), coordinate()}, 0.1f);
  }
  spheres.set(17, {std::numeric_limits<float>::quiet_NaN(), 0, 0}, 0.1f);
  for (int ranks = 1; ranks <= 5; ++ranks) {
    std::vector<int> owners(spheres.size(), 0);
    double volumes = 0;
    const auto all_at_once = sphray::mpi::spatial_shares(spheres.view(), ranks);
    ASSERT_EQ(all_at_once.size(), static_cast<std::size_t>(ranks));
    for (int rank = 0; rank < ranks; ++rank) {
      const std::vector<std::uint32_t> ids =
          sphray::mpi::spatial_share(spheres.view(), rank, ranks);
      EXPECT_EQ(ids, all_at_once[static_cast<std::size_t>(rank)]);
      EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()));
      EXPECT_NEAR(static_cast<double>(ids.size()), 4000.0 / ranks, 1.0);
      volumes += centres_box_volume(spheres, ids, owners);
    }
    // The scene's box is 10^3; a split by id gives ranks boxes of nearly that each. Runs of a
    // Morton curve cut at other than powers of two are not boxes, so their boxes overlap some.
    if (ranks > 1) {
      EXPECT_LT(volumes, 0.7 * 1000.0 * ranks) << ranks << " ranks";
    }
    for (std::size_t id = 0; id < owners.size(); ++id)
      EXPECT_EQ(owners[id], 1) << "sphere " << id << ", " << ranks << " ranks";
  }
  EXPECT_THROW(sphray::mpi::spatial_share(spheres.view(), 2, 2), std::invalid_argument);
}

// n small spheres in the box [0, 10] x [0, 20] x [0, 10].
sphray::SphereSoA tall_box(int n, unsigned seed) {
  std::mt19937 rng(seed);
  sphray::SphereSoA spheres;
  for (int i = 0; i < n; ++i) {
    const auto coordinate = [&] { return static_cast<float>(rng() % 100000) * 1e-4f; };
    spheres.add({coordinate(), 2 * coordinate(), coordinate()}, 0.01f);
  }
  return spheres;
}

TEST(MpiSpatialSplit, PlaneSharesAreDisjointBoxesOfEqualCounts) {
  sphray::SphereSoA spheres = tall_box(5000, 4);
  spheres.set(17, {std::numeric_limits<float>::quiet_NaN(), 0, 0}, 0.1f);
  for (int ranks : {1, 2, 3, 5, 8, 13}) {
    const auto shares = sphray::mpi::plane_shares(spheres.view(), ranks);
    ASSERT_EQ(shares.size(), static_cast<std::size_t>(ranks));
    std::vector<int> owners(spheres.size(), 0);
    double volumes = 0;
    for (int rank = 0; rank < ranks; ++rank) {
      const auto& ids = shares[static_cast<std::size_t>(rank)];
      EXPECT_EQ(ids, sphray::mpi::plane_share(spheres.view(), rank, ranks)) << rank;
      EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()));
      EXPECT_NEAR(static_cast<double>(ids.size()), 5000.0 / ranks, 2.0);
      volumes += centres_box_volume(spheres, ids, owners);
    }
    // Cells of planes through the centres: their centres' boxes tile the scene's (10 x 20 x 10)
    // without overlap, so their volumes add up to at most the scene's.
    EXPECT_LE(volumes, 2000.0 * 1.0001) << ranks << " ranks";
    for (std::size_t id = 0; id < owners.size(); ++id)
      EXPECT_EQ(owners[id], 1) << "sphere " << id << ", " << ranks << " ranks";
  }
  EXPECT_THROW(sphray::mpi::plane_shares(spheres.view(), 0), std::invalid_argument);
  EXPECT_THROW(sphray::mpi::plane_share(spheres.view(), 3, 3), std::invalid_argument);
}

// Weights choose the axes of the cuts: the scene is longest along y, but weighted by a camera
// whose rows run along z, every cut is across z, and each share is a slab of it.
TEST(MpiSpatialSplit, WeightsChooseTheAxisOfTheCuts) {
  const sphray::SphereSoA spheres = tall_box(4000, 5);
  for (int ranks : {2, 4}) {
    const auto shares = sphray::mpi::plane_shares(spheres.view(), ranks, {0, 0, 1});
    float previous_high = -1.0f;
    for (int rank = 0; rank < ranks; ++rank) {
      const auto& ids = shares[static_cast<std::size_t>(rank)];
      EXPECT_EQ(ids, sphray::mpi::plane_share(spheres.view(), rank, ranks, {0, 0, 1}));
      float low = INFINITY, high = -INFINITY;
      for (std::uint32_t id : ids) {
        low = std::min(low, spheres.center(id).z);
        high = std::max(high, spheres.center(id).z);
      }
      EXPECT_GE(low, previous_high) << "rank " << rank << " of " << ranks;  // slabs in z order
      previous_high = high;
    }
  }
  // Unweighted, the first cut is across y, the longest axis: rank 0 keeps the low half of y.
  const auto halves = sphray::mpi::plane_shares(spheres.view(), 2);
  float high = -INFINITY;
  for (std::uint32_t id : halves[0])
    high = std::max(high, spheres.center(id).y);
  for (std::uint32_t id : halves[1])
    EXPECT_GE(spheres.center(id).y, high);
}

}  // namespace
