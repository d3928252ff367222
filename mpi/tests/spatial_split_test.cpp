// spatial_share: every sphere goes to exactly one rank, in runs of equal size, and the ranks own
// compact regions: their boxes together are well below the ranks' count times the scene's (a
// split by id gives every rank nearly the whole scene's box).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sphray/mpi/regions.hpp"
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

// The fraction of probes that enter shares[0]'s region before shares[1]'s, of those that enter
// either.
double first_in_lower(const sphray::SphereSoA& spheres,
                      const std::vector<std::vector<std::uint32_t>>& shares,
                      const std::vector<sphray::Ray>& probes) {
  const sphray::mpi::RegionBox regions[2] = {sphray::mpi::region_box(spheres.view(), shares[0]),
                                             sphray::mpi::region_box(spheres.view(), shares[1])};
  double lower = 0, either = 0;
  for (const sphray::Ray& probe : probes) {
    const int first = sphray::mpi::next_region(regions, probe, probe.tmax, {}).region;
    if (first < 0) continue;
    either += 1;
    lower += first == 0 ? 1 : 0;
  }
  return lower / either;
}

// Probes (a camera's rays) move the cut to where they divide, not the spheres: seen from above
// a corner, the upper half of a box is entered first by three rays in four; cut by the rays,
// each share's region takes half of them, and each keeps at least a quarter of the spheres.
TEST(MpiSpatialSplit, ProbesBalanceTheRaysNotTheSpheres) {
  const sphray::SphereSoA spheres = tall_box(4000, 6);
  std::mt19937 rng(7);
  std::vector<sphray::Ray> probes;
  for (int i = 0; i < 1024; ++i) {
    const auto at = [&](float side) { return static_cast<float>(rng() % 1000) * side * 1e-3f; };
    const sphray::Vec3 from{30, 40, 30}, to{at(10), at(20), at(10)};
    probes.push_back(sphray::Ray{from, to - from});
  }
  const auto by_count = sphray::mpi::plane_shares(spheres.view(), 2);
  EXPECT_LT(first_in_lower(spheres, by_count, probes), 0.3);  // the cut is across y
  const auto by_rays = sphray::mpi::plane_shares(spheres.view(), 2, {1, 1, 1}, probes);
  EXPECT_NEAR(first_in_lower(spheres, by_rays, probes), 0.5, 0.05);
  for (const auto& share : by_rays) {
    EXPECT_GE(share.size(), 1000u);
    EXPECT_LE(share.size(), 3000u);
  }
  EXPECT_EQ(by_rays[1], sphray::mpi::plane_share(spheres.view(), 1, 2, {1, 1, 1}, probes));
}

// Probes that cannot place a cut leave the cut by count: rays that enter neither side, centres
// that do not spread along the axis, slabs too wide or too narrow for a float.
TEST(MpiSpatialSplit, ProbesThatTellNothingLeaveTheCutByCount) {
  const sphray::SphereSoA spheres = tall_box(4000, 8);
  const std::vector<sphray::Ray> away(16, sphray::Ray{{0, -5, 0}, {0, -1, 0}});
  EXPECT_EQ(sphray::mpi::plane_shares(spheres.view(), 3, {1, 1, 1}, away),
            sphray::mpi::plane_shares(spheres.view(), 3));
  sphray::SphereSoA same_place;
  for (int i = 0; i < 100; ++i)
    same_place.add({1, 2, 3}, 0.5f + static_cast<float>(i) * 0.01f);
  const std::vector<sphray::Ray> through(16, sphray::Ray{{-10, 2, 3}, {1, 0, 0}});
  const auto shares = sphray::mpi::plane_shares(same_place.view(), 2, {1, 1, 1}, through);
  EXPECT_EQ(shares, sphray::mpi::plane_shares(same_place.view(), 2));
  EXPECT_EQ(shares[0].size(), 50u);
  // Centres so far apart that a slab's width overflows, or so near that it underflows.
  for (const float step : {6.5e36f, 1e-45f}) {
    sphray::SphereSoA extreme;
    for (int i = -50; i < 50; ++i)
      extreme.add({static_cast<float>(i) * step, 0, 0}, 1.0f);
    const std::vector<sphray::Ray> across(16, sphray::Ray{{0, -10, 0}, {0, 1, 0}});
    EXPECT_EQ(sphray::mpi::plane_shares(extreme.view(), 2, {1, 1, 1}, across),
              sphray::mpi::plane_shares(extreme.view(), 2))
        << step;
  }
}

}  // namespace
