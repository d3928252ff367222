// The tree in double precision (SphereBVHd): on every instruction set, each query (closest, any
// and every crossing) against brute force in double on the same spheres, bit for bit, where the
// tree's float boxes are coarsest (millimetre spheres at 100 km), for spheres float cannot hold at
// all, for the contract's invalid inputs, and after a refit.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "double_support.hpp"
#include "test_support.hpp"

namespace sphray {
namespace {

using namespace test::doubles;

// The tree's answers to ray against brute force's in double (the scalar reference), bit for
// bit; returns whether the ray hit.
bool expect_tree_answers(const SphereBVHd& tree, SphereViewd v, const Rayd& ray) {
  const Hitd want = scalar::intersect(v, ray);
  const Hitd got = intersect(tree, ray);
  EXPECT_TRUE(same_bits(want, got))
      << isa_name(tree.isa()) << ": want " << describe(want) << ", got " << describe(got);
  EXPECT_EQ(occluded(tree, ray), scalar::occluded(v, ray)) << isa_name(tree.isa());
  return want.found();
}

// Trees of 0 to 3000 spheres (flat ones answered by brute force, walked ones with each leaf
// test), at the origin and at 1e5, unmasked and masked.
TEST(DoubleTree, EveryKernelGivesBruteForceBits) {
  std::mt19937 rng(3710);
  const std::size_t counts[] = {0, 1, 2, 5, 9, 33, 100, 600, 3000};
  const Vec3d places[] = {{0, 0, 0}, {1e5, -2e5, 3e4}};
  for (const EntryTable* k : test::runnable_kernels()) {
    std::size_t hits = 0, compared = 0;
    bool branch_free = false, branching = false;
    for (const std::size_t n : counts) {
      for (const Vec3d at : places) {
        // Dense scenes (overlapping leaves: the branch-free leaf test) and sparse ones, their
        // radii a tenth.
        for (const double shrink : {1.0, 0.1}) {
          const double scale = 6.0 / std::cbrt(static_cast<double>(n) + 1.0);
          DoubleSpheres scene = random_spheres(rng, n, at, scale);
          for (std::size_t i = 0; i < n; ++i)
            scene.storage[3][DoubleSpheres::kOffset + i] *= shrink;
          for (const bool masked : {false, true}) {
            const SphereViewd v = scene.view(masked);
            const SphereBVHd tree(v, k->isa);
            ASSERT_EQ(tree.size(), n);
            const auto& data = detail::BvhAccess::data(tree);
            if (!data.flat && data.count > 1) {
              (data.leaf_overlap >= detail::kBvhBranchFreeOverlap ? branch_free : branching) = true;
            }
            for (std::size_t i = 0; i < test::scaled(200); ++i) {
              Rayd ray = random_ray(rng, at, 1.0);
              if (masked) ray.mask = static_cast<std::uint32_t>(rng());
              hits += expect_tree_answers(tree, v, ray) ? 1 : 0;
              ++compared;
              if (HasFailure()) return;
            }
          }
        }
      }
    }
    EXPECT_TRUE(branch_free && branching) << test::name_of(k);
    EXPECT_GT(hits, compared / 20) << test::name_of(k);
    EXPECT_LT(hits, compared) << test::name_of(k);
  }
}

// Where a double tree's float boxes are coarsest: 2000 spheres of 1 mm radius, 2.5 mm apart
// on average, 100 km from the origin, where float's spacing is 8 mm. The boxes, rounded
// outward, overlap; the answers stay exact.
TEST(DoubleTree, MillimetresAtAHundredKilometres) {
  std::mt19937 rng(3711);
  const Vec3d at{1e5, -1e5, 5e4};
  DoubleSpheres scene;
  for (std::size_t i = 0; i < 2000; ++i)
    scene.add(at + 0.015 * in_box(rng, 1.0), 1e-3 * uniform(rng, 0.5, 1.0));
  const SphereViewd v = scene.view();
  for (const EntryTable* k : test::runnable_kernels()) {
    const SphereBVHd tree(v, k->isa);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < test::scaled(2000); ++i) {
      const Vec3d from = at + 0.1 * normalize(in_box(rng, 1.0));
      const Vec3d to = at + 0.012 * in_box(rng, 1.0);
      hits += expect_tree_answers(tree, v, Rayd{from, to - from}) ? 1 : 0;
      if (HasFailure()) return;
    }
    EXPECT_GT(hits, test::scaled(2000) / 4) << test::name_of(k);
  }
}

// Spheres that are valid in double but beyond float: a centre at 1e100, a radius of 2^-500.
// Their float boxes are unbounded or as small as float goes; both are hit, among enough other
// spheres that the tree is walked.
TEST(DoubleTree, SpheresBeyondFloatsRangeAreHit) {
  std::mt19937 rng(3712);
  DoubleSpheres scene;
  for (std::size_t i = 0; i < 500; ++i)
    scene.add(in_box(rng, 100.0) + Vec3d{0, 0, 300}, 1.0);
  const std::uint32_t far_id = static_cast<std::uint32_t>(scene.size());
  scene.add({0, 0, -1e100}, 1e99);
  const std::uint32_t tiny_id = static_cast<std::uint32_t>(scene.size());
  scene.add({0.5, 0.25, 0}, 0x1p-500);
  const SphereViewd v = scene.view();
  const Rayd to_far{{0, 0, 0}, {0, 0, -1}};
  const Rayd to_tiny{{0.5, 0.25, -1}, {0, 0, 1}};
  for (const EntryTable* k : test::runnable_kernels()) {
    const SphereBVHd tree(v, k->isa);
    EXPECT_EQ(intersect(tree, to_far).id, far_id) << test::name_of(k);
    EXPECT_EQ(intersect(tree, to_tiny).id, tiny_id) << test::name_of(k);
    expect_tree_answers(tree, v, to_far);
    expect_tree_answers(tree, v, to_tiny);
    for (std::size_t i = 0; i < test::scaled(300); ++i)
      expect_tree_answers(tree, v, random_ray(rng, {0, 0, 200}, 10.0));
  }
}

// Spheres so small and so near the origin (|c| + r below 2^-130) that float's boxes are made
// of denormals, where 2^-20 of a coordinate rounds to nothing: rays grazing them, whose hits
// double's rounding puts just outside the exact sphere, must still enter the box. The first
// case was found by the kernel fuzzer: a ray 2^-264 outside a sphere of radius 2^-133 that
// touches the plane z = 0. The others are alike: spheres on float's grid (2^-149) touching a
// coordinate plane, passed by rays a relative 2^-60 or so beyond it, where double rounds the
// distance to the radius.
TEST(DoubleTree, GrazingHitsOnSpheresBelowFloatsNormals) {
  std::mt19937 rng(3716);
  DoubleSpheres scene;
  scene.add({0.0, 0x1.7d8cp-254, 0x1.fffffep-133}, 0x1.fffffep-133);
  const Rayd found{{-0x1.72ap-257, 0x1.d7p-259, -0x1.bp-264}, {-0x1.45p+384, 0x1.42p+383, 0.0}};
  const auto on_grid = [&](int lo, int hi) {
    return std::ldexp(static_cast<double>(lo + static_cast<int>(rng() % (hi - lo + 1))), -149);
  };
  const auto at = [](Vec3d& v, int axis) -> double& {
    return axis == 0 ? v.x : axis == 1 ? v.y : v.z;
  };
  for (std::size_t i = 0; i < 300; ++i) {
    // Sphere i touches the plane through the origin across axis i % 3.
    const double r = on_grid(4, 64);
    Vec3d c{on_grid(-1024, 1024), on_grid(-1024, 1024), on_grid(-1024, 1024)};
    at(c, static_cast<int>(i % 3)) = rng() % 2 ? r : -r;
    scene.add(c, r);
  }
  const SphereViewd v = scene.view();
  for (const EntryTable* k : test::runnable_kernels()) {
    const SphereBVHd tree(v, k->isa);
    EXPECT_TRUE(expect_tree_answers(tree, v, found)) << test::name_of(k);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < test::scaled(1000); ++i) {
      // Along another axis, from outside every sphere, just beyond the plane sphere id touches.
      const auto id = static_cast<std::uint32_t>(1 + rng() % (scene.size() - 1));
      const int plane = static_cast<int>((id - 1) % 3), along = (plane + 1 + rng() % 2) % 3;
      Vec3d origin{v.cx[id], v.cy[id], v.cz[id]}, dir{0, 0, 0};
      const double beyond = v.radius[id] * std::ldexp(static_cast<double>(rng() % 5), -60);
      at(origin, plane) = at(origin, plane) > 0 ? -beyond : beyond;
      at(origin, along) -= 0x1p-130;
      at(dir, along) = 1.0;
      hits += expect_tree_answers(tree, v, Rayd{origin, dir}) ? 1 : 0;
      if (HasFailure()) return;
    }
    EXPECT_GT(hits, 0u) << test::name_of(k);
  }
}

// The contract's invalid spheres among valid ones never widen a box or get hit, and invalid
// rays miss with t == tmax, through the walk.
TEST(DoubleTree, InvalidRaysAndSpheresMiss) {
  std::mt19937 rng(3713);
  DoubleSpheres scene;
  const double bad_radii[] = {0.0, -1.0, kNaN, kInf, 0x1p-512, 0x1p512};
  for (std::size_t i = 0; i < 400; ++i) {
    if (i % 5 == 0)
      scene.add(i % 10 == 0 ? Vec3d{kNaN, 0, 0} : Vec3d{0, 0, 0}, bad_radii[i % 6]);
    else
      scene.add(in_box(rng, 20.0), 1.0);
  }
  const SphereViewd v = scene.view();
  const Rayd bad_rays[] = {
      {{kNaN, 0, -5}, {0, 0, 1}},         {{0, 0, -5}, {0, 0, 0}},
      {{0, 0, -5}, {0, 0, 1e-170}},       {{0, 0, -5}, {0, 0, 1}, 2.0, 1.0},
      {{0, 0, -5}, {0, 0, 1}, 0.0, kNaN}, {{0, 0, -5}, {0, 0, 1}, 0.0, kInf, 0u},
  };
  for (const EntryTable* k : test::runnable_kernels()) {
    const SphereBVHd tree(v, k->isa);
    for (const Rayd& ray : bad_rays) {
      const Hitd hit = intersect(tree, ray);
      EXPECT_FALSE(hit.found()) << test::name_of(k);
      EXPECT_EQ(std::bit_cast<std::uint64_t>(hit.t), std::bit_cast<std::uint64_t>(ray.tmax));
      EXPECT_FALSE(occluded(tree, ray)) << test::name_of(k);
    }
    std::size_t hits = 0;
    for (std::size_t i = 0; i < test::scaled(500); ++i)
      hits += expect_tree_answers(tree, v, random_ray(rng, {0, 0, 0}, 2.0)) ? 1 : 0;
    EXPECT_GT(hits, 0u) << test::name_of(k);
  }
}

// Equal spheres: the lower id wins, however the leaves order them.
TEST(DoubleTree, TiesGoToTheLowerId) {
  DoubleSpheres scene;
  std::mt19937 rng(3714);
  for (std::size_t i = 0; i < 300; ++i)
    scene.add(in_box(rng, 30.0), 0.5);
  for (std::size_t i = 0; i < 20; ++i)
    scene.add({0, 0, 0}, 1.0);
  const SphereViewd v = scene.view();
  for (const EntryTable* k : test::runnable_kernels()) {
    const SphereBVHd tree(v, k->isa);
    const Hitd hit = intersect(tree, Rayd{{0, 0, -0.5}, {0, 0, 1}});
    EXPECT_EQ(hit.id, 300u) << test::name_of(k);
    EXPECT_EQ(hit.t, 1.5) << test::name_of(k);
  }
}

// The every-hit batch forms in double answer each ray as its single query does, on a view and
// on a tree; sizes that do not fit throw.
TEST(DoubleTree, EveryHitBatchFormsAnswerEachRayAsItsSingleQuery) {
  std::mt19937 rng(3717);
  const DoubleSpheres scene = random_spheres(rng, 400, {5e4, 0, -5e4}, 0.4);
  const SphereViewd v = scene.view();
  const SphereBVHd tree(v);
  std::vector<Rayd> rays(test::scaled(300));
  for (Rayd& r : rays)
    r = random_ray(rng, {5e4, 0, -5e4}, 0.4);
  constexpr std::size_t kPerRay = 3;
  std::vector<Hitd> out(rays.size() * kPerRay), one(kPerRay);
  std::vector<std::size_t> counts(rays.size());
  std::size_t crossings = 0;
  for (const bool nearest_only : {false, true}) {
    for (const bool through_tree : {false, true}) {
      if (nearest_only)
        through_tree ? intersect_nearest(tree, rays, out, kPerRay, counts)
                     : intersect_nearest(v, rays, out, kPerRay, counts);
      else
        through_tree ? intersect_all(tree, rays, out, kPerRay, counts)
                     : intersect_all(v, rays, out, kPerRay, counts);
      std::vector<std::size_t> totals(rays.size());
      through_tree ? count_hits(tree, rays, totals) : count_hits(v, rays, totals);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const std::size_t total =
            through_tree ? intersect_all(tree, rays[i], one) : intersect_all(v, rays[i], one);
        ASSERT_EQ(totals[i], total) << i;
        ASSERT_EQ(counts[i], nearest_only ? std::min(total, kPerRay) : total) << i;
        for (std::size_t k = 0; k < std::min(total, kPerRay); ++k)
          ASSERT_TRUE(same_bits(out[i * kPerRay + k], one[k])) << i << ", slot " << k;
        crossings += total;
      }
    }
  }
  EXPECT_GT(crossings, rays.size());
  std::vector<std::size_t> short_counts(rays.size() - 1);
  EXPECT_THROW(intersect_all(tree, rays, out, kPerRay, short_counts), std::length_error);
  EXPECT_THROW(count_hits(v, rays, short_counts), std::length_error);
  std::vector<Hitd> short_out(out.size() - 1);
  EXPECT_THROW(intersect_nearest(v, rays, short_out, kPerRay, counts), std::length_error);
}

// Refit takes moved spheres and answers as a fresh brute force on them; a different count
// throws, and a moved-from tree misses every ray.
TEST(DoubleTree, RefitAndMove) {
  std::mt19937 rng(3715);
  DoubleSpheres scene = random_spheres(rng, 700, {1e4, 0, 0}, 0.5);
  SphereBVHd tree(scene.view());
  for (std::size_t s = 0; s < 4; ++s)
    for (std::size_t i = 0; i < scene.size(); ++i)
      scene.storage[s][DoubleSpheres::kOffset + i] += s == 3 ? 0.1 : uniform(rng, -1.0, 1.0);
  tree.refit(scene.view());
  for (std::size_t i = 0; i < test::scaled(500); ++i)
    expect_tree_answers(tree, scene.view(), random_ray(rng, {1e4, 0, 0}, 0.5));
  const DoubleSpheres other = random_spheres(rng, 5, {0, 0, 0}, 1.0);
  EXPECT_THROW(tree.refit(other.view()), std::invalid_argument);
  SphereBVHd moved = std::move(tree);
  const Rayd ray{{1e4, 0, -50}, {0, 0, 1}};
  EXPECT_TRUE(intersect(moved, ray).found());
  EXPECT_FALSE(intersect(tree, ray).found());  // NOLINT(bugprone-use-after-move): specified
  EXPECT_EQ(tree.size(), 0u);
}

// Every crossing through the tree: the list, its exits and the total against brute force's
// double reference, bit for bit, at capacities from none to more than there are; the nearest
// crossings alone as the list's first ones.
TEST(DoubleTree, EveryCrossingAndTheNearestGiveBruteForceBits) {
  std::mt19937 rng(3717);
  std::size_t crossings = 0;
  for (const EntryTable* k : test::runnable_kernels()) {
    for (const std::size_t n : {1, 9, 300, 2000}) {
      const DoubleSpheres scene = random_spheres(rng, n, {1e4, 0, -1e4}, 1.5);
      for (const bool masked : {false, true}) {
        const SphereViewd v = scene.view(masked);
        const SphereBVHd tree(v, k->isa);
        for (std::size_t i = 0; i < test::scaled(100); ++i) {
          Rayd ray = random_ray(rng, {1e4, 0, -1e4}, 1.0);
          if (masked) ray.mask = static_cast<std::uint32_t>(rng());
          for (const std::size_t capacity : {0, 1, 3, 64}) {
            std::vector<Hitd> want(capacity), got(capacity), nearest(capacity);
            std::vector<char> want_exits(capacity + 1), got_exits(capacity + 1),
                nearest_exits(capacity + 1);
            const auto flags = [capacity](std::vector<char>& f) {
              return std::span(reinterpret_cast<bool*>(f.data()), capacity);
            };
            const std::size_t total = scalar::intersect_all(v, ray, want, flags(want_exits));
            ASSERT_EQ(intersect_all(tree, ray, got, flags(got_exits)), total) << test::name_of(k);
            ASSERT_EQ(count_hits(tree, ray), total) << test::name_of(k);
            const std::size_t kept = intersect_nearest(tree, ray, nearest, flags(nearest_exits));
            ASSERT_EQ(kept, std::min(capacity, total)) << test::name_of(k);
            for (std::size_t j = 0; j < kept; ++j) {
              ASSERT_TRUE(same_bits(want[j], got[j])) << test::name_of(k) << " crossing " << j;
              ASSERT_TRUE(same_bits(want[j], nearest[j])) << test::name_of(k) << " nearest " << j;
              ASSERT_EQ(want_exits[j], got_exits[j]) << test::name_of(k);
              ASSERT_EQ(want_exits[j], nearest_exits[j]) << test::name_of(k);
            }
            crossings += capacity == 0 ? total : 0;
          }
        }
      }
    }
  }
  EXPECT_GT(crossings, 1000u);
}

TEST(DoubleTree, StreamsAnswerAsSingleQueriesAndCheckTheirSizes) {
  std::mt19937 rng(3716);
  const DoubleSpheres scene = random_spheres(rng, 900, {0, 0, 0}, 0.7);
  const SphereBVHd tree(scene.view());
  std::vector<Rayd> rays(257);
  for (Rayd& r : rays)
    r = random_ray(rng, {0, 0, 0}, 1.0);
  std::vector<Hitd> hits(rays.size());
  std::unique_ptr<bool[]> blocked(new bool[rays.size()]);
  intersect(tree, rays, hits);
  occluded(tree, rays, std::span(blocked.get(), rays.size()));
  for (std::size_t i = 0; i < rays.size(); ++i) {
    EXPECT_TRUE(same_bits(hits[i], scalar::intersect(scene.view(), rays[i])));
    EXPECT_EQ(blocked[i], scalar::occluded(scene.view(), rays[i]));
  }
  EXPECT_THROW(intersect(tree, rays, std::span(hits).first(3)), std::length_error);
  EXPECT_THROW(occluded(tree, rays, std::span(blocked.get(), 3)), std::length_error);
}

}  // namespace
}  // namespace sphray
