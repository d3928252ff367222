// The regions a routed ray visits: their order along the ray, the bound that skips the ones
// beyond a hit, and invalid rays, which visit none.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "sphray/mpi/regions.hpp"

namespace {

using sphray::Ray;
using sphray::SphereSoA;
using sphray::mpi::next_region;
using sphray::mpi::RegionBox;
using sphray::mpi::RegionKey;

// Three regions along x, each around one unit sphere at x = 0, 10, 20; region 3 holds only a
// sphere that can never be hit, so it is empty.
std::vector<RegionBox> row_of_regions() {
  std::vector<RegionBox> regions;
  for (float x : {20.0f, 0.0f, 10.0f}) {  // not in x order: the order comes from the ray
    SphereSoA one;
    one.add({x, 0, 0}, 1.0f);
    regions.push_back(sphray::mpi::region_box(one.view()));
  }
  SphereSoA never;
  never.add({5, 0, 0}, -1.0f);
  regions.push_back(sphray::mpi::region_box(never.view()));
  return regions;
}

// The regions a ray visits in turn, with no hit to stop it.
std::vector<int> visits(const std::vector<RegionBox>& regions, const Ray& ray, float bound) {
  std::vector<int> order;
  RegionKey at;
  for (;;) {
    at = next_region(regions, ray, bound, at);
    if (at.region < 0) return order;
    order.push_back(at.region);
  }
}

TEST(Regions, ABoxHoldsItsSpheresPadded) {
  const std::vector<RegionBox> regions = row_of_regions();
  EXPECT_FALSE(regions[1].empty);
  EXPECT_LT(regions[1].lo[0], -1.0f);
  EXPECT_GT(regions[1].hi[0], 1.0f);
  EXPECT_LT(regions[1].hi[0], 1.001f);
  EXPECT_TRUE(regions[3].empty);
}

TEST(Regions, ARayVisitsTheRegionsItCrossesFrontToBack) {
  const std::vector<RegionBox> regions = row_of_regions();
  EXPECT_EQ(visits(regions, Ray{{-5, 0, 0}, {1, 0, 0}}, INFINITY), (std::vector<int>{1, 2, 0}));
  EXPECT_EQ(visits(regions, Ray{{30, 0, 0}, {-1, 0, 0}}, INFINITY), (std::vector<int>{0, 2, 1}));
  // From inside the middle region: it and the one ahead; tmax ends the segment before the last.
  EXPECT_EQ(visits(regions, Ray{{10, 0, 0}, {1, 0, 0}}, INFINITY), (std::vector<int>{2, 0}));
  EXPECT_EQ(visits(regions, Ray{{-5, 0, 0}, {1, 0, 0}, 0.0f, 15.0f}, 15.0f),
            (std::vector<int>{1, 2}));
  EXPECT_EQ(visits(regions, Ray{{-5, 0, 0}, {1, 0, 0}, 0.0f, 12.0f}, 12.0f), (std::vector<int>{1}));
  // Beside the row, and along y through one region only (a zero direction component in x).
  EXPECT_TRUE(visits(regions, Ray{{-5, 3, 0}, {1, 0, 0}}, INFINITY).empty());
  EXPECT_EQ(visits(regions, Ray{{10, -5, 0}, {0, 1, 0}}, INFINITY), (std::vector<int>{2}));
}

TEST(Regions, ARegionBeyondTheNearestHitIsSkipped) {
  const std::vector<RegionBox> regions = row_of_regions();
  const Ray ray{{-5, 0, 0}, {1, 0, 0}};
  const RegionKey first = next_region(regions, ray, INFINITY, RegionKey{});
  ASSERT_EQ(first.region, 1);
  // A hit at t = 4 (x = -1) in region 1: region 2 starts at t = 14, beyond it.
  EXPECT_EQ(next_region(regions, ray, 4.0f, first).region, -1);
  EXPECT_EQ(next_region(regions, ray, 13.0f, first).region, -1);
  // A hit exactly where a region starts keeps it: an equal t with a lower id may lie there.
  const RegionKey second = next_region(regions, ray, INFINITY, first);
  ASSERT_EQ(second.region, 2);
  EXPECT_NEAR(second.entry, 14.0f, 1e-3f);
  EXPECT_EQ(next_region(regions, ray, second.entry, first).region, 2);
}

TEST(Regions, AnInvalidRayVisitsNothing) {
  const std::vector<RegionBox> regions = row_of_regions();
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = INFINITY;
  for (const Ray& ray : {Ray{{nan, 0, 0}, {1, 0, 0}}, Ray{{-5, 0, 0}, {nan, 0, 0}},
                         Ray{{-inf, 0, 0}, {1, 0, 0}}, Ray{{-5, 0, 0}, {inf, 0, 0}},
                         Ray{{-5, 0, 0}, {0, 0, 0}}, Ray{{-5, 0, 0}, {1, 0, 0}, nan, inf}}) {
    EXPECT_EQ(next_region(regions, ray, ray.tmax, RegionKey{}).region, -1);
  }
  EXPECT_EQ(next_region(regions, Ray{{-5, 0, 0}, {1, 0, 0}}, nan, RegionKey{}).region, -1);
}

// What a routed ray carries to skip the search after a visit: `then` is the entry of the next
// region after the next one, and a region entered beyond reach(bound) is never visited.
TEST(Regions, ThenIsTheEntryOfTheRegionAfterTheNext) {
  const std::vector<RegionBox> regions = row_of_regions();
  const Ray ray{{-5, 0, 0}, {1, 0, 0}};
  const sphray::mpi::RegionSteps first = sphray::mpi::next_regions(regions, ray, INFINITY, {});
  EXPECT_EQ(first.next.region, 1);
  const RegionKey second = next_region(regions, ray, INFINITY, first.next);
  EXPECT_EQ(second.region, 2);
  EXPECT_EQ(first.then, second.entry);
  // The last region has none after it.
  const RegionKey last = next_region(regions, ray, INFINITY, second);
  EXPECT_EQ(sphray::mpi::next_regions(regions, ray, INFINITY, last).then, INFINITY);
  // A hit at t = 6 (x = 1) is short of region 2, entered at about t = 14: nothing left.
  EXPECT_GT(first.then, sphray::mpi::reach(ray, 6.0f));
  EXPECT_EQ(next_region(regions, ray, 6.0f, first.next).region, -1);
  // A hit at t = 14.5 is not: region 2 is still visited.
  EXPECT_LE(first.then, sphray::mpi::reach(ray, 14.5f));
  EXPECT_TRUE(std::isnan(sphray::mpi::reach(Ray{{0, 0, 0}, {0, 0, 0}}, 1.0f)));
}

}  // namespace
