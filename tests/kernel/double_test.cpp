// The queries in double precision: every instruction set's double kernel against the double
// scalar reference bit for bit, both against a long-double reference for hit or miss and
// distance, the contract's invalid rays and spheres as misses, and a scene float cannot resolve
// (a 1 mm sphere 100 km from the origin) answered as exact arithmetic answers it.
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "double_support.hpp"
#include "test_support.hpp"

namespace sphray {
namespace {

using namespace test::doubles;

// Views of 0 to 300 spheres (every partial batch of every width among them) at the origin and
// at 1e5, unmasked and masked, and random rays through them: each kernel's double queries
// against the double scalar reference, bit for bit.
TEST(Double, EveryKernelGivesTheScalarReferenceBits) {
  std::mt19937 rng(37);
  const std::size_t counts[] = {0, 1, 2, 3, 5, 7, 8, 9, 13, 16, 17, 31, 40, 300};
  const Vec3d places[] = {{0, 0, 0}, {1e5, -2e5, 3e4}};
  for (const EntryTable* k : test::runnable_kernels()) {
    ASSERT_NE(k->intersect_d, nullptr) << test::name_of(k);
    std::size_t hits = 0, compared = 0;
    for (const std::size_t n : counts) {
      for (const Vec3d at : places) {
        const double scale = 6.0 / std::cbrt(static_cast<double>(n) + 1.0);
        const DoubleSpheres scene = random_spheres(rng, n, at, scale);
        for (const bool masked : {false, true}) {
          const SphereViewd v = scene.view(masked);
          for (std::size_t i = 0; i < test::scaled(300); ++i) {
            Rayd ray = random_ray(rng, at, 1.0);
            if (masked) ray.mask = static_cast<std::uint32_t>(rng());
            const Hitd want = scalar::intersect(v, ray);
            const Hitd got = k->intersect_d(v, ray);
            ASSERT_TRUE(same_bits(want, got))
                << test::name_of(k) << " n " << n << " masked " << masked << ": want "
                << describe(want) << ", got " << describe(got);
            ASSERT_EQ(k->occluded_d(v, ray), scalar::occluded(v, ray)) << test::name_of(k);
            ASSERT_TRUE(same_bits(want, intersect(v, ray)));  // the dispatched query
            hits += want.found() ? 1 : 0;
            ++compared;
          }
        }
      }
    }
    // The scenes are made so that many rays hit: a run of misses would prove little.
    EXPECT_GT(hits, compared / 10) << test::name_of(k);
    EXPECT_LT(hits, compared) << test::name_of(k);
  }
}

// Hit or miss and distance against the long-double reference, at three scales of the world
// (1, 1e5 and 1e-3 units) on every kernel. A ray whose answer rounding may decide is left out
// and counted: a graze (relative discriminant below 1e-9) or a second sphere within 1e-9 of the
// closest t.
TEST(Double, AgreesWithALongDoubleReference) {
  std::mt19937 rng(3701);
  struct World {
    Vec3d at;
    double scale;
  };
  const World worlds[] = {{{0, 0, 0}, 1.0}, {{1e5, 1e5, -1e5}, 1.0}, {{0.5, -2, 1}, 1e-3}};
  for (const EntryTable* k : test::runnable_kernels()) {
    std::size_t checked = 0, left_out = 0, hits = 0;
    for (const World& w : worlds) {
      const DoubleSpheres scene = random_spheres(rng, 40, w.at, w.scale * 1.5);
      const SphereViewd v = scene.view();
      for (std::size_t i = 0; i < test::scaled(2000); ++i) {
        const Rayd ray = random_ray(rng, w.at, w.scale);
        std::optional<Real> best;
        std::uint32_t best_id = kNoHit;
        bool ambiguous = false;
        for (std::uint32_t s = 0; s < v.count; ++s) {
          const Exact e = exact_hit(ray, {v.cx[s], v.cy[s], v.cz[s]}, v.radius[s]);
          if (std::fabs(e.relative_disc) < 1e-9) ambiguous = true;
          if (!e.t) continue;
          if (best && std::fabs(*e.t - *best) <= 1e-9 * std::fabs(*best)) ambiguous = true;
          if (!best || *e.t < *best) best = e.t, best_id = s;
        }
        if (ambiguous) {
          ++left_out;
          continue;
        }
        const Hitd got = k->intersect_d(v, ray);
        ASSERT_EQ(got.id, best_id) << test::name_of(k);
        if (best) {
          // The roots as the kernel computes them err by a few units of double's roundoff of
          // the distances involved: t's own, and the ray's from the spheres (a ray starting
          // inside or beside a sphere has a t far smaller than them).
          const double scene_t = 40.0 * w.scale / length(ray.dir);
          EXPECT_NEAR(static_cast<double>(got.t), static_cast<double>(*best),
                      1e-13 * (static_cast<double>(std::fabs(*best)) + scene_t))
              << test::name_of(k);
          ++hits;
        }
        ++checked;
      }
    }
    EXPECT_LT(left_out, checked / 20) << test::name_of(k);
    EXPECT_GT(hits, checked / 4) << test::name_of(k);
  }
}

// The contract's invalid inputs in double: every one misses on every kernel, and a valid ray
// and sphere beside them still hit (the test could fail).
TEST(Double, InvalidRaysAndSpheresMiss) {
  const Rayd good{{0, 0, -5}, {0, 0, 1}};
  const Rayd bad_rays[] = {
      {{kNaN, 0, -5}, {0, 0, 1}},         {{0, kInf, -5}, {0, 0, 1}},
      {{0, 0, -5}, {0, 0, kNaN}},         {{0, 0, -5}, {0, 0, 0}},
      {{0, 0, -5}, {0, 0, 1e-170}},  // |dir|^2 below DBL_MIN
      {{0, 0, -5}, {0, 0, 1e170}},   // |dir|^2 overflows
      {{0, 0, -5}, {0, 0, 1}, 2.0, 1.0},  {{0, 0, -5}, {0, 0, 1}, kNaN, 10.0},
      {{0, 0, -5}, {0, 0, 1}, 0.0, kNaN}, {{0, 0, -5}, {0, 0, 1}, 0.0, kInf, 0u},
  };
  for (const EntryTable* k : test::runnable_kernels()) {
    // A batch's worth of one valid sphere with invalid ones around it, for each lane width.
    for (std::size_t lane = 0; lane < 9; ++lane) {
      DoubleSpheres scene;
      for (std::size_t i = 0; i < 9; ++i)
        scene.add({0, 0, 0}, i == lane ? 1.0 : 0.0);
      const SphereViewd v = scene.view();
      const Hitd hit = k->intersect_d(v, good);
      EXPECT_EQ(hit.id, lane) << test::name_of(k);
      EXPECT_EQ(hit.t, 4.0) << test::name_of(k);
      for (const Rayd& ray : bad_rays) {
        EXPECT_FALSE(k->intersect_d(v, ray).found()) << test::name_of(k);
        EXPECT_EQ(std::bit_cast<std::uint64_t>(k->intersect_d(v, ray).t),
                  std::bit_cast<std::uint64_t>(ray.tmax))
            << test::name_of(k);
        EXPECT_FALSE(k->occluded_d(v, ray)) << test::name_of(k);
      }
    }
    const double bad_radii[] = {0.0, -1.0, kNaN, kInf, 0x1p-512, 0x1p512, 1e200};
    const Vec3d bad_centres[] = {{kNaN, 0, 0}, {0, kInf, 0}, {0, 0, -kInf}};
    DoubleSpheres scene;
    for (const double r : bad_radii)
      scene.add({0, 0, 0}, r);
    for (const Vec3d c : bad_centres)
      scene.add(c, 1.0);
    for (std::size_t i = 0; i < 10; ++i)
      scene.add({0, 0, 0}, bad_radii[i % 7]);
    EXPECT_FALSE(k->intersect_d(scene.view(), good).found()) << test::name_of(k);
    EXPECT_FALSE(k->occluded_d(scene.view(), good)) << test::name_of(k);
    scene.add({0, 0, 0}, 0x1p-511);  // the smallest valid radius: hit
    EXPECT_EQ(k->intersect_d(scene.view(), good).id, scene.size() - 1) << test::name_of(k);
  }
}

// A 1 mm sphere 100 km from the origin, as a survey or a city model has them: in float its
// centre and radius are not representable (float's spacing at 1e5 is 1/128), in double the
// kernel finds where exact arithmetic puts the ray's entry, and misses it by a hair's breadth.
TEST(Double, ResolvesAMillimetreAtAHundredKilometres) {
  const Vec3d centre{1e5 + 0.25, -3e4, 7e4};
  const double radius = 1e-3;
  DoubleSpheres scene;
  scene.add(centre, radius);
  scene.add(centre + Vec3d{0.0, 2.5e-3, 0.0}, radius);  // a second one beside it
  const SphereViewd v = scene.view();
  for (const EntryTable* k : test::runnable_kernels()) {
    for (const double offset : {0.0, 0.5e-3, 0.99e-3, 1.01e-3, 1.5e-3}) {
      const Rayd ray{centre + Vec3d{-1.0, offset, 0.0}, {1, 0, 0}};
      const Exact want = exact_hit(ray, centre, radius);
      const Hitd got = k->intersect_d(v, ray);
      ASSERT_EQ(got.found(), want.t.has_value()) << test::name_of(k) << " offset " << offset;
      if (!want.t) continue;
      EXPECT_EQ(got.id, 0u);
      // 1 - sqrt(r^2 - offset^2): to within a few nanometres.
      EXPECT_NEAR(got.t, static_cast<double>(*want.t), 1e-9) << test::name_of(k);
      const Surfaced s = surface(v, ray, got);
      // On the sphere but for the point's rounding: double's spacing at 1e5 is 1.5e-11.
      EXPECT_NEAR(length(s.point - centre), radius, 3e-11);
      EXPECT_TRUE(s.front_face);
    }
  }
}

// Rays spawned from the 1 mm sphere at 100 km: outward they never meet it again, inward they
// meet its far side where the long-double reference puts it.
TEST(Double, SpawnLeavesAndCrossesAMillimetreAtAHundredKilometres) {
  std::mt19937 rng(3702);
  const Vec3d centre{1e5, 2e4, -1e5};
  const double radius = 1e-3;
  DoubleSpheres scene;
  scene.add(centre, radius);
  const SphereViewd v = scene.view();
  std::size_t inward = 0;
  for (std::size_t i = 0; i < test::scaled(4000); ++i) {
    const Vec3d from = centre + 2.0 * normalize(in_box(rng, 1.0));
    const Vec3d target = centre + 0.9 * radius * normalize(in_box(rng, 1.0));
    const Rayd ray{from, target - from};
    const Hitd hit = intersect(v, ray);
    ASSERT_TRUE(hit.found());
    const Surfaced s = surface(v, ray, hit);
    Vec3d dir = normalize(in_box(rng, 1.0));
    const bool in = dot(dir, s.normal) < 0;
    const Hitd next = intersect(v, spawn(s, dir));
    if (!in) {
      EXPECT_FALSE(next.found()) << "outward ray " << i << " met the sphere again";
      continue;
    }
    ++inward;
    ASSERT_TRUE(next.found()) << "inward ray " << i << " missed the far side";
    const Exact want = exact_hit(spawn(s, dir), centre, radius);
    ASSERT_TRUE(want.t.has_value());
    EXPECT_NEAR(next.t, static_cast<double>(*want.t), 1e-12);
  }
  EXPECT_GT(inward, test::scaled(4000) / 4);
}

// Every crossing in double: each kernel's list, its exits and its total against the double
// scalar reference's bit for bit, at capacities from none to more than there are, and the first
// crossing against the closest hit (which the list must start with).
TEST(Double, EveryCrossingGivesTheScalarReferenceBits) {
  std::mt19937 rng(3704);
  std::size_t crossings = 0;
  for (const EntryTable* k : test::runnable_kernels()) {
    for (const std::size_t n : {0, 1, 3, 9, 40, 300}) {
      const DoubleSpheres scene = random_spheres(rng, n, {1e4, 0, -1e4}, 1.5);
      for (const bool masked : {false, true}) {
        const SphereViewd v = scene.view(masked);
        for (std::size_t i = 0; i < test::scaled(200); ++i) {
          Rayd ray = random_ray(rng, {1e4, 0, -1e4}, 1.0);
          if (masked) ray.mask = static_cast<std::uint32_t>(rng());
          for (const std::size_t capacity : {0, 1, 3, 64}) {
            std::vector<Hitd> want(capacity), got(capacity);
            std::unique_ptr<bool[]> want_exits(new bool[capacity + 1]),
                got_exits(new bool[capacity + 1]);
            const std::size_t total =
                scalar::intersect_all(v, ray, want, std::span(want_exits.get(), capacity));
            ASSERT_EQ(k->intersect_all_d(v, ray, got.data(), got_exits.get(), capacity), total)
                << test::name_of(k);
            for (std::size_t j = 0; j < std::min(capacity, total); ++j) {
              ASSERT_TRUE(same_bits(want[j], got[j])) << test::name_of(k) << " crossing " << j;
              ASSERT_EQ(want_exits[j], got_exits[j]) << test::name_of(k);
            }
            ASSERT_EQ(count_hits(v, ray), total);
            const Hitd closest = scalar::intersect(v, ray);
            ASSERT_EQ(total > 0, closest.found());
            if (capacity > 0 && total > 0) {
              ASSERT_TRUE(same_bits(want[0], closest));
            }
            crossings += capacity == 0 ? total : 0;
          }
        }
      }
    }
  }
  EXPECT_GT(crossings, 1000u);  // the scenes are crossed often enough to prove something
}

// SphereSoAd: aligned arrays padded with never-hit spheres, whose views every kernel reads in
// whole batches, with the answers of the same spheres in unpadded arrays; masks, set and copies
// as SphereSoA's.
TEST(Double, SphereSoAdIsPaddedAndAnswersAsItsSpheres) {
  std::mt19937 rng(3705);
  const DoubleSpheres loose = random_spheres(rng, 37, {1e5, 0, 0}, 1e-3);
  SphereSoAd soa;
  for (std::size_t i = 0; i < loose.size(); ++i) {
    const SphereViewd v = loose.view(true);
    EXPECT_EQ(soa.add({v.cx[i], v.cy[i], v.cz[i]}, v.radius[i], v.mask[i]), i);
  }
  const SphereViewd view = soa.view();
  ASSERT_EQ(view.count, 37u);
  EXPECT_EQ(view.padded_count, 48u);
  for (const double* array : {view.cx, view.cy, view.cz, view.radius})
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(array) % SphereSoAd::kAlignment, 0u);
  for (std::size_t i = view.count; i < view.padded_count; ++i)
    EXPECT_EQ(view.radius[i], 0.0);
  EXPECT_EQ(soa.center(5).x, loose.view().cx[5]);  // the doubles as given, not rounded
  for (const EntryTable* k : test::runnable_kernels()) {
    for (std::size_t i = 0; i < test::scaled(300); ++i) {
      Rayd ray = random_ray(rng, {1e5, 0, 0}, 1e-3);
      ray.mask = static_cast<std::uint32_t>(rng());
      ASSERT_TRUE(same_bits(k->intersect_d(view, ray), scalar::intersect(loose.view(true), ray)))
          << test::name_of(k);
    }
  }
  const SphereSoAd copy = soa;
  EXPECT_EQ(copy.size(), soa.size());
  EXPECT_EQ(copy.mask(7), soa.mask(7));
  soa.set(0, {1, 2, 3}, 0.5);
  EXPECT_EQ(soa.radius(0), 0.5);
  EXPECT_NE(copy.radius(0), 0.5);
  EXPECT_THROW(soa.set(37, {0, 0, 0}, 1.0), std::out_of_range);
}

TEST(Double, StreamsAnswerAsSingleQueriesAndCheckTheirSizes) {
  std::mt19937 rng(3703);
  const DoubleSpheres scene = random_spheres(rng, 50, {0, 0, 0}, 1.5);
  std::vector<Rayd> rays(257);
  for (Rayd& r : rays)
    r = random_ray(rng, {0, 0, 0}, 1.0);
  std::vector<Hitd> hits(rays.size());
  std::unique_ptr<bool[]> blocked(new bool[rays.size()]);
  intersect(scene.view(), rays, hits);
  occluded(scene.view(), rays, std::span(blocked.get(), rays.size()));
  for (std::size_t i = 0; i < rays.size(); ++i) {
    EXPECT_TRUE(same_bits(hits[i], scalar::intersect(scene.view(), rays[i])));
    EXPECT_EQ(blocked[i], scalar::occluded(scene.view(), rays[i]));
  }
  EXPECT_THROW(intersect(scene.view(), rays, std::span(hits).first(3)), std::length_error);
  EXPECT_THROW(occluded(scene.view(), rays, std::span(blocked.get(), 3)), std::length_error);
}

}  // namespace
}  // namespace sphray
