// DistributedScene against the single-process kernel: the same spheres split over the ranks in
// several ways must answer every query exactly as the scalar reference does over all of them.
// Every rank builds the whole scene from the same seed, keeps its share, and checks every
// answer against the reference over the whole.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "sphray/mpi/distributed_scene.hpp"
#include "sphray/sphray.hpp"
#include "world.hpp"

namespace {

using sphray::mpi::test::rank;
using sphray::mpi::test::ranks;

using sphray::Hit;
using sphray::Nearest;
using sphray::Ray;
using sphray::SphereSoA;
using sphray::Vec3;
using sphray::mpi::DistributedScene;

float uniform(std::mt19937& rng, float lo, float hi) {
  return lo + (hi - lo) * static_cast<float>(rng() >> 8) * 0x1p-24f;
}

// Spheres in a 20-unit box, some masked, a few invalid (never hit, on any rank).
SphereSoA random_spheres(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  SphereSoA spheres;
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 c{uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -10, 10)};
    float r = uniform(rng, 0.05f, 1.5f);
    if (i % 97 == 5) r = -r;
    if (i % 89 == 7) c.x = std::numeric_limits<float>::quiet_NaN();
    const std::uint32_t mask = i % 5 == 0 ? 0x2u : sphray::kAllBits;
    spheres.add(c, r, mask);
  }
  return spheres;
}

// Rays from outside and inside the box, aimed at spheres or anywhere, some bounded, some masked,
// some invalid (NaN, zero direction, empty interval).
std::vector<Ray> random_rays(const SphereSoA& spheres, std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<Ray> rays(n);
  for (std::size_t i = 0; i < n; ++i) {
    Ray& ray = rays[i];
    ray.origin = {uniform(rng, -15, 15), uniform(rng, -15, 15), uniform(rng, -15, 15)};
    const auto target = static_cast<std::uint32_t>(rng() % spheres.size());
    ray.dir = i % 3 == 0 ? Vec3{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)}
                         : spheres.center(target) - ray.origin;
    if (i % 7 == 0) ray.tmax = uniform(rng, 0.2f, 1.0f);
    if (i % 11 == 0) ray.tmin = uniform(rng, 0.0f, 0.5f);
    if (i % 13 == 0) ray.mask = 0x1u;
    if (i % 101 == 3) ray.dir = {0, 0, 0};
    if (i % 103 == 4) ray.origin.y = std::numeric_limits<float>::quiet_NaN();
    if (i % 107 == 5) ray.tmin = ray.tmax;
  }
  return rays;
}

// This rank's share of spheres: those owner(id) gives it, in an order other than by id (the
// scene must sort them itself).
struct Share {
  SphereSoA spheres;
  std::vector<std::uint32_t> ids;
};

Share share_of(const SphereSoA& all, const std::function<int(std::uint32_t)>& owner) {
  Share share;
  for (std::size_t k = all.size(); k-- > 0;) {
    const auto id = static_cast<std::uint32_t>(k);
    if (owner(id) != rank()) continue;
    share.spheres.add(all.center(id), all.radius(id), all.mask(id));
    share.ids.push_back(id);
  }
  return share;
}

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Every query of the distributed scene against the scalar reference over all spheres.
void expect_reference_answers(const SphereSoA& all, const DistributedScene& scene,
                              const std::vector<Ray>& rays) {
  const sphray::SphereView view = all.view();
  std::vector<Hit> hits(rays.size());
  scene.intersect(rays, hits);
  std::vector<char> occluded_storage(rays.size());
  std::span<bool> occluded(reinterpret_cast<bool*>(occluded_storage.data()), rays.size());
  scene.occluded(rays, occluded);
  std::vector<std::size_t> counts(rays.size());
  scene.count_hits(rays, counts);
  int mismatches = 0;
  for (std::size_t i = 0; i < rays.size() && mismatches < 10; ++i) {
    const Hit expected = sphray::scalar::intersect(view, rays[i]);
    const bool ok = expected.id == hits[i].id && same_bits(expected.t, hits[i].t) &&
                    occluded[i] == sphray::scalar::occluded(view, rays[i]) &&
                    counts[i] == sphray::count_hits(view, rays[i]);
    if (!ok) ++mismatches;
    EXPECT_TRUE(ok) << "ray " << i << ": id " << hits[i].id << " t " << hits[i].t
                    << ", expected id " << expected.id << " t " << expected.t;
  }
}

// This rank's own rays for the routed queries: unequal runs of rays (rank r of p takes
// [n r^2 / p^2, n (r + 1)^2 / p^2): rank 0 the fewest), with their indices in rays.
std::vector<std::size_t> own_rays(std::size_t n) {
  const auto p = static_cast<std::size_t>(ranks()), r = static_cast<std::size_t>(rank());
  std::vector<std::size_t> mine;
  for (std::size_t i = n * r * r / (p * p); i < n * (r + 1) * (r + 1) / (p * p); ++i)
    mine.push_back(i);
  return mine;
}

// The routed queries, each rank asking for its own rays, against the scalar reference.
void expect_routed_answers(const SphereSoA& all, const DistributedScene& scene,
                           const std::vector<Ray>& rays) {
  const std::vector<std::size_t> mine = own_rays(rays.size());
  std::vector<Ray> asked;
  for (std::size_t i : mine)
    asked.push_back(rays[i]);
  std::vector<Hit> hits(asked.size());
  scene.intersect_routed(asked, hits);
  std::vector<char> occluded_storage(asked.size());
  std::span<bool> occluded(reinterpret_cast<bool*>(occluded_storage.data()), asked.size());
  scene.occluded_routed(asked, occluded);
  int mismatches = 0;
  for (std::size_t k = 0; k < asked.size() && mismatches < 10; ++k) {
    const Hit expected = sphray::scalar::intersect(all.view(), asked[k]);
    const bool ok = expected.id == hits[k].id && same_bits(expected.t, hits[k].t) &&
                    occluded[k] == sphray::scalar::occluded(all.view(), asked[k]);
    if (!ok) ++mismatches;
    EXPECT_TRUE(ok) << "ray " << mine[k] << ": id " << hits[k].id << " t " << hits[k].t
                    << ", expected id " << expected.id << " t " << expected.t;
  }
}

void expect_reference_nearest(const SphereSoA& all, const DistributedScene& scene,
                              float max_distance) {
  std::mt19937 rng(77);
  std::vector<Vec3> points(500);
  for (Vec3& p : points)
    p = {uniform(rng, -12, 12), uniform(rng, -12, 12), uniform(rng, -12, 12)};
  points[3].z = std::numeric_limits<float>::infinity();
  std::vector<Nearest> out(points.size());
  scene.nearest(points, out, max_distance);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Nearest expected = sphray::scalar::nearest(all.view(), points[i], max_distance);
    EXPECT_EQ(out[i].id, expected.id) << "point " << i;
    EXPECT_TRUE(same_bits(out[i].distance, expected.distance)) << "point " << i;
    EXPECT_TRUE(same_bits(out[i].point.x, expected.point.x) &&
                same_bits(out[i].point.y, expected.point.y) &&
                same_bits(out[i].point.z, expected.point.z))
        << "point " << i;
  }
}

// Each rank a slab of [-10, 10] along x (the spheres of random_spheres), in rank order.
Share slabs_of(const SphereSoA& all) {
  return share_of(all, [&all](std::uint32_t id) {
    const float x = all.center(id).x;
    const int slab = std::isfinite(x) ? static_cast<int>((x + 10.0f) / 20.0f * ranks()) : 0;
    return std::clamp(slab, 0, ranks() - 1);
  });
}

TEST(MpiReductions, ScatteredSpheresMatchTheSingleProcessKernel) {
  const SphereSoA all = random_spheres(3000, 1);
  // Spheres dealt out by a hash of their id: every rank's share spans the whole box.
  const Share share = share_of(
      all, [](std::uint32_t id) { return static_cast<int>((id * 2654435761u) >> 7) % ranks(); });
  const DistributedScene scene(MPI_COMM_WORLD, share.spheres.view(), share.ids);
  EXPECT_EQ(scene.global_size(), all.size());
  expect_reference_answers(all, scene, random_rays(all, 4000, 2));
  expect_routed_answers(all, scene, random_rays(all, 4000, 2));
  expect_reference_nearest(all, scene, sphray::kAnyDistance);
  expect_reference_nearest(all, scene, 0.5f);
}

TEST(MpiReductions, SlabsOfSpaceMatchTheSingleProcessKernel) {
  const SphereSoA all = random_spheres(3000, 3);
  // Each rank a slab along x, as a spatial split gives; rays cross several slabs.
  const Share share = slabs_of(all);
  const DistributedScene scene(MPI_COMM_WORLD, share.spheres.view(), share.ids);
  expect_reference_answers(all, scene, random_rays(all, 4000, 4));
  expect_routed_answers(all, scene, random_rays(all, 4000, 4));
  expect_reference_nearest(all, scene, sphray::kAnyDistance);
}

// Ranks that make different numbers of routed calls (a path tracer's tiles bounce unequally):
// rank r asks for its rays in r + 1 calls, then finishes, answering the others' rays until
// all have finished. Every answer is still the reference's, and the ranks go on together.
TEST(MpiReductions, UnevenRoutedCallsEndWithFinish) {
  const SphereSoA all = random_spheres(3000, 5);
  const Share share = slabs_of(all);
  const DistributedScene scene(MPI_COMM_WORLD, share.spheres.view(), share.ids);
  const std::vector<Ray> rays = random_rays(all, 4000, 6);
  const std::vector<std::size_t> mine = own_rays(rays.size());
  const auto calls = static_cast<std::size_t>(rank()) + 1;
  std::vector<Ray> asked;
  for (std::size_t i : mine)
    asked.push_back(rays[i]);
  std::vector<Hit> hits(asked.size());
  for (std::size_t c = 0; c < calls; ++c) {
    const std::size_t begin = asked.size() * c / calls, end = asked.size() * (c + 1) / calls;
    scene.intersect_routed(std::span(asked).subspan(begin, end - begin),
                           std::span(hits).subspan(begin, end - begin));
  }
  scene.finish_routed();
  for (std::size_t k = 0; k < asked.size(); ++k) {
    const Hit expected = sphray::scalar::intersect(all.view(), asked[k]);
    ASSERT_TRUE(expected.id == hits[k].id && same_bits(expected.t, hits[k].t))
        << "ray " << mine[k] << ": id " << hits[k].id << ", expected id " << expected.id;
  }
  // The ranks left finish_routed together: the next calls pair up again.
  expect_routed_answers(all, scene, random_rays(all, 1000, 7));
}

// Ranks that disagree on the kind of a routed call are told so, all of them, not left waiting.
TEST(MpiReductions, RoutedCallsOfDifferentKindsAreRefusedOnEveryRank) {
  const SphereSoA all = random_spheres(300, 8);
  const Share share =
      share_of(all, [](std::uint32_t id) { return static_cast<int>(id) % ranks(); });
  const DistributedScene scene(MPI_COMM_WORLD, share.spheres.view(), share.ids);
  const std::vector<Ray> rays = random_rays(all, 50, 9);
  std::vector<Hit> hits(rays.size());
  std::vector<char> storage(rays.size());
  const std::span<bool> blocked(reinterpret_cast<bool*>(storage.data()), rays.size());
  const bool mixed = ranks() > 1;  // rank 0 asks for hits, the others for occlusion
  try {
    if (rank() == 0)
      scene.intersect_routed(rays, hits);
    else
      scene.occluded_routed(rays, blocked);
    EXPECT_FALSE(mixed) << "rank " << rank() << " answered a mixed call";
  } catch (const std::logic_error& e) {
    EXPECT_TRUE(mixed) << e.what();
  }
}

TEST(MpiReductions, EqualTOnTwoRanksGoesToTheLowerGlobalId) {
  // Spheres 2k and 2k + 1 are the same sphere; the higher id lives on the lower rank whenever
  // there are two ranks or more, so each tie is settled across ranks by the reduction.
  SphereSoA all;
  std::mt19937 rng(5);
  for (int k = 0; k < 200; ++k) {
    const Vec3 c{uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -10, 10)};
    const float r = uniform(rng, 0.2f, 1.0f);
    all.add(c, r);
    all.add(c, r);
  }
  const Share share = share_of(all, [](std::uint32_t id) {
    const int pair = static_cast<int>(id / 2);
    return id % 2 == 1 ? pair % ranks() : (pair + 1) % ranks();
  });
  const DistributedScene scene(MPI_COMM_WORLD, share.spheres.view(), share.ids);
  const std::vector<Ray> rays = random_rays(all, 2000, 6);
  std::vector<Hit> hits(rays.size());
  scene.intersect(rays, hits);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (hits[i].found()) {
      EXPECT_EQ(hits[i].id % 2, 0u) << "ray " << i;
    }
  }
  expect_reference_answers(all, scene, rays);
  expect_routed_answers(all, scene, rays);
  expect_reference_nearest(all, scene, sphray::kAnyDistance);
}

TEST(MpiReductions, RoutedRaysVisitOnlyTheRegionsBeforeTheirHit) {
  // A row of unit spheres along x, split into slabs, and rays along +x from the left: each ray
  // hits a sphere in the first slab, so no other rank traces it. Rays beside the row cross no
  // region and are traced nowhere.
  SphereSoA all;
  for (int k = 0; k < 64; ++k)
    all.add({3.0f * static_cast<float>(k), 0, 0}, 1.0f);
  const Share share =
      share_of(all, [](std::uint32_t id) { return static_cast<int>(id) * ranks() / 64; });
  const DistributedScene scene(MPI_COMM_WORLD, share.spheres.view(), share.ids);
  std::vector<Ray> rays;
  for (int k = 0; k < 100; ++k) {
    const float y = -0.9f + 0.018f * static_cast<float>(k);
    rays.push_back(Ray{{-10, y, 0}, {1, 0, 0}});      // hits sphere 0
    rays.push_back(Ray{{-10, y + 5, 0}, {1, 0, 0}});  // beside the row
  }
  expect_routed_answers(all, scene, rays);
  unsigned long long traced = scene.route_counts().traced, asked = scene.route_counts().asked;
  MPI_Allreduce(MPI_IN_PLACE, &traced, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &asked, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(asked, 2 * rays.size());  // both queries
  EXPECT_EQ(traced, rays.size());     // the 100 rays that hit, once each, per query
  if (rank() != 0) {
    EXPECT_EQ(scene.route_counts().traced, 0u);  // only rank 0 holds sphere 0
  }
}

TEST(MpiReductions, ARankWithoutSpheresTakesPart) {
  const SphereSoA all = random_spheres(1000, 7);
  // With two ranks or more the last one holds nothing; with one, it holds everything.
  const int holders = std::max(1, ranks() - 1);
  const Share share = share_of(all, [holders](std::uint32_t id) {
    return static_cast<int>(id % static_cast<std::uint32_t>(holders));
  });
  if (ranks() > 1 && rank() == ranks() - 1) {
    EXPECT_EQ(share.ids.size(), 0u);
  }
  const DistributedScene scene(MPI_COMM_WORLD, share.spheres.view(), share.ids);
  expect_reference_answers(all, scene, random_rays(all, 2000, 8));
  expect_routed_answers(all, scene, random_rays(all, 2000, 8));
  expect_reference_nearest(all, scene, 3.0f);
}

TEST(MpiReductions, NoSpheresAnywhereIsAllMisses) {
  const SphereSoA none;
  const DistributedScene scene(MPI_COMM_WORLD, none.view(), {});
  EXPECT_EQ(scene.global_size(), 0u);
  std::vector<Ray> rays(3);
  rays[0] = Ray{{0, 0, 0}, {0, 0, -1}};
  rays[1] = Ray{{1, 2, 3}, {1, 0, 0}, 0.0f, 5.0f};
  rays[2] = Ray{{0, 0, 0}, {0, 0, 0}};
  std::vector<Hit> hits(rays.size());
  scene.intersect(rays, hits);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    EXPECT_EQ(hits[i].id, sphray::kNoHit);
    EXPECT_TRUE(same_bits(hits[i].t, rays[i].tmax));
  }
  std::vector<Hit> routed(rays.size());
  scene.intersect_routed(rays, routed);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    EXPECT_EQ(routed[i].id, sphray::kNoHit);
    EXPECT_TRUE(same_bits(routed[i].t, rays[i].tmax));
  }
  EXPECT_EQ(scene.route_counts().traced, 0u);
}

TEST(MpiReductions, RepeatedIdsAreRefused) {
  SphereSoA two;
  two.add({0, 0, 0}, 1);
  two.add({3, 0, 0}, 1);
  const std::vector<std::uint32_t> twice{4, 4};
  EXPECT_THROW(DistributedScene(MPI_COMM_WORLD, two.view(), twice), std::invalid_argument);
  const std::vector<std::uint32_t> one{4};
  EXPECT_THROW(DistributedScene(MPI_COMM_WORLD, two.view(), one), std::invalid_argument);
}

TEST(MpiReductions, AShareRefusedOnOneRankStopsEveryRank) {
  // Only rank 0 repeats an id; had the others gone on to their first reduction, they would wait
  // for rank 0 for ever (ctest's timeout would catch that).
  SphereSoA two;
  two.add({0, 0, 0}, 1);
  two.add({3, 0, 0}, 1);
  const auto base = static_cast<std::uint32_t>(2 * rank());
  const std::vector<std::uint32_t> ids =
      rank() == 0 ? std::vector<std::uint32_t>{0, 0} : std::vector<std::uint32_t>{base, base + 1};
  try {
    const DistributedScene scene(MPI_COMM_WORLD, two.view(), ids);
    ADD_FAILURE() << "rank " << rank() << " built a scene";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "sphere id 0 given twice");  // rank 0's reason, on every rank
  }
}

}  // namespace
