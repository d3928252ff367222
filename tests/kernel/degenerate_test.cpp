// Degenerate spheres and rays: a defined miss on every instruction set, never a crash.
#include <bit>
#include <cfloat>
#include <cmath>
#include <limits>

#include "test_support.hpp"

namespace sphray {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kDenormal = std::numeric_limits<float>::denorm_min();

// Views of n copies of one sphere, so both the scalar path (n = 1) and whole and partial SIMD
// batches (n = 19, 40) see it.
test::LooseSpheres copies(Vec3 c, float r, std::size_t n) {
  test::LooseSpheres s;
  for (std::size_t i = 0; i < n; ++i)
    s.add(c, r);
  return s;
}

void expect_miss_everywhere(const test::LooseSpheres& s, const Ray& ray) {
  auto expect_miss = [&](const Hit& h) {
    EXPECT_EQ(h.id, kNoHit);
    // The miss reports tmax itself (NaN compares unequal to itself, so compare its bits).
    EXPECT_EQ(std::bit_cast<std::uint32_t>(h.t), std::bit_cast<std::uint32_t>(ray.tmax));
  };
  for (const EntryTable* k : test::runnable_kernels()) {
    SCOPED_TRACE(test::name_of(k) + " n " + std::to_string(s.count));
    expect_miss(k->intersect(s.view(), ray));
    EXPECT_FALSE(k->occluded(s.view(), ray));
    Hit streamed{};
    k->intersect_stream(s.view(), &ray, &streamed, 1);
    expect_miss(streamed);
  }
  expect_miss(scalar::intersect(s.view(), ray));
}

const Ray kTowardsOrigin{{0, 0, 10}, {0, 0, -1}};

TEST(Degenerate, InvalidSpheresAreNeverHit) {
  const float bad_radii[] = {0.0f, -1.0f, -kInf, kInf, kNaN, kDenormal, 1e-20f, 0x1p64f, FLT_MAX};
  const float bad_coords[] = {kNaN, kInf, -kInf};
  for (std::size_t n : {1u, 19u, 40u}) {
    for (float r : bad_radii)
      expect_miss_everywhere(copies({0, 0, 0}, r, n), kTowardsOrigin);
    for (float v : bad_coords) {
      expect_miss_everywhere(copies({v, 0, 0}, 1.0f, n), kTowardsOrigin);
      expect_miss_everywhere(copies({0, v, 0}, 1.0f, n), kTowardsOrigin);
      expect_miss_everywhere(copies({0, 0, v}, 1.0f, n), kTowardsOrigin);
    }
  }
}

// Issue 30: a sphere whose radius squared underflows to 0 (here a denormal radius) was hit at
// t = 0x1p-148 by brute force on every instruction set and by the AVX2 tree, for a ray whose
// closest approach is about 8e6 radii, while the scalar and SSE4.2 trees missed it and the
// scalar count_hits and occluded disagreed. Such a sphere is invalid (r * r must be a normal
// float): every query answers as for radius 0.
TEST(Degenerate, RadiusWhoseSquareUnderflowsIsNeverHit) {
  std::mt19937 rng(30);
  SphereSoA tiny, zero;
  tiny.add({0, 1e-20f, 0}, 1e-45f);
  zero.add({0, 1e-20f, 0}, 0.0f);
  for (int i = 0; i < 199; ++i) {
    const Vec3 c = test::random_in_box(rng, 10.0f);
    const float r = test::uniform(rng, 0.2f, 1.5f);
    tiny.add(c, r);
    zero.add(c, r);
  }
  const Ray ray{{1.17e-38f, 1e-20f, 1e-45f}, {1e-20f, 0.46f, -0.51f}};
  auto same = [](const Hit& a, const Hit& b) {
    return a.id == b.id && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t);
  };
  const Hit expected = scalar::intersect(zero.view(), ray);
  EXPECT_TRUE(same(scalar::intersect(tiny.view(), ray), expected));
  EXPECT_EQ(scalar::occluded(tiny.view(), ray), expected.found());
  EXPECT_EQ(scalar::intersect_all(tiny.view(), ray, {}, {}) > 0, expected.found());
  for (const EntryTable* k : test::runnable_kernels()) {
    SCOPED_TRACE(test::name_of(k));
    const SphereBVH bvh(tiny.view(), k->isa);
    EXPECT_TRUE(same(k->intersect(tiny.view(), ray), expected));
    EXPECT_TRUE(same(intersect(bvh, ray), expected));
    EXPECT_EQ(k->occluded(tiny.view(), ray), expected.found());
    EXPECT_EQ(occluded(bvh, ray), expected.found());
    EXPECT_EQ(k->intersect_all(tiny.view(), ray, nullptr, nullptr, 0) > 0, expected.found());
    EXPECT_EQ(count_hits(bvh, ray) > 0, expected.found());
    // The point queries do not find it either, even at its centre.
    EXPECT_NE(k->nearest(tiny.view(), {0, 1e-20f, 0}, INFINITY).id, 0u);
    EXPECT_NE(nearest(bvh, {0, 1e-20f, 0}).id, 0u);
  }
}

// The bounds of the rule: a radius is valid from 2^-63 (whose square is FLT_MIN, the smallest
// normal float) and below 2^64 (whose square overflows), as the ray's direction length is.
TEST(Degenerate, RadiusBoundsAreWhereItsSquareIsANormalFloat) {
  const float lowest = 0x1p-63f, below = std::nextafter(lowest, 0.0f);
  const float highest = std::nextafter(0x1p64f, 0.0f), above = 0x1p64f;
  // Through the centre from outside for the small ones; from the centre for the huge ones,
  // which hit their far side at t = r.
  const Ray small_ray{{-1e-18f, 0, 0}, {1, 0, 0}};
  const Ray huge_ray{{0, 0, 0}, {1, 0, 0}};
  for (std::size_t n : {1u, 19u, 40u}) {
    for (const EntryTable* k : test::runnable_kernels()) {
      SCOPED_TRACE(test::name_of(k) + " n " + std::to_string(n));
      const auto valid_small = copies({0, 0, 0}, lowest, n);
      const auto valid_huge = copies({0, 0, 0}, highest, n);
      EXPECT_TRUE(k->intersect(valid_small.view(), small_ray).found());
      EXPECT_TRUE(intersect(SphereBVH(valid_small.view(), k->isa), small_ray).found());
      EXPECT_EQ(k->intersect(valid_huge.view(), huge_ray).t, highest);
      EXPECT_EQ(intersect(SphereBVH(valid_huge.view(), k->isa), huge_ray).t, highest);
      EXPECT_TRUE(inside(valid_small.view(), {0, 0, 0}));
      EXPECT_TRUE(inside(valid_huge.view(), {0, 0, 0}));
      EXPECT_EQ(k->nearest(valid_huge.view(), {0, 0, 0}, INFINITY).id, 0u);
      EXPECT_EQ(k->nearest(valid_small.view(), {0, 0, 0}, INFINITY).id, 0u);
    }
    expect_miss_everywhere(copies({0, 0, 0}, below, n), small_ray);
    expect_miss_everywhere(copies({0, 0, 0}, above, n), huge_ray);
    for (float r : {below, above, -lowest}) {
      const auto s = copies({0, 0, 0}, r, n);
      EXPECT_FALSE(inside(s.view(), {0, 0, 0})) << r;
      EXPECT_FALSE(nearest(s.view(), {0, 0, 0}).found()) << r;
      EXPECT_FALSE(scalar::nearest(s.view(), {0, 0, 0}).found()) << r;
      for (const EntryTable* k : test::runnable_kernels()) {
        const SphereBVH bvh(s.view(), k->isa);
        EXPECT_EQ(k->nearest(s.view(), {0, 0, 0}, INFINITY).id, kNoHit) << test::name_of(k);
        EXPECT_FALSE(inside(bvh, {0, 0, 0})) << test::name_of(k) << " " << r;
        EXPECT_FALSE(intersect(bvh, r == above ? huge_ray : small_ray).found()) << r;
      }
    }
  }
}

TEST(Degenerate, InvalidSpheresDoNotHideValidOnes) {
  for (const EntryTable* k : test::runnable_kernels()) {
    test::LooseSpheres s;
    for (int i = 0; i < 30; ++i)
      s.add({0, 0, i % 2 ? kNaN : kInf}, i % 3 ? -1.0f : kNaN);
    s.add({0, 0, 0}, 1.0f);  // id 30
    const Hit hit = k->intersect(s.view(), kTowardsOrigin);
    EXPECT_EQ(hit.id, 30u) << test::name_of(k);
    EXPECT_FLOAT_EQ(hit.t, 9.0f);
  }
}

TEST(Degenerate, InvalidRaysMissEverything) {
  const float bad[] = {kNaN, kInf, -kInf};
  std::vector<Ray> rays;
  for (float v : bad) {
    for (int axis = 0; axis < 3; ++axis) {
      Ray r = kTowardsOrigin;
      (axis == 0 ? r.origin.x : axis == 1 ? r.origin.y : r.origin.z) = v;
      rays.push_back(r);
      r = kTowardsOrigin;
      (axis == 0 ? r.dir.x : axis == 1 ? r.dir.y : r.dir.z) = v;
      rays.push_back(r);
    }
  }
  auto with = [](float tmin, float tmax) {
    Ray r = kTowardsOrigin;
    r.tmin = tmin;
    r.tmax = tmax;
    return r;
  };
  rays.push_back(Ray{{0, 0, 10}, {0, 0, 0}});           // zero direction
  rays.push_back(Ray{{0, 0, 10}, {0, 0, -kDenormal}});  // |d|^2 underflows to 0
  rays.push_back(Ray{{0, 0, 10}, {0, 0, -1e20f}});      // |d|^2 overflows to inf
  rays.push_back(with(kNaN, 100.0f));
  rays.push_back(with(0.0f, kNaN));
  rays.push_back(with(5.0f, 5.0f));   // empty interval
  rays.push_back(with(20.0f, 5.0f));  // reversed interval
  rays.push_back(with(kInf, kInf));
  for (std::size_t n : {0u, 1u, 19u, 40u}) {
    const auto s = copies({0, 0, 0}, 1.0f, n);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      SCOPED_TRACE("ray " + std::to_string(i));
      expect_miss_everywhere(s, rays[i]);
    }
  }
}

TEST(Degenerate, InfiniteTmaxAndNegativeTminAreValid) {
  // tmin = -inf, tmax = +inf: the near root, here behind the origin at t = -11 + 20 = ... from
  // (0,0,10) along -z the roots are 9 and 11; with tmin = -inf the near root 9 is taken.
  for (const EntryTable* k : test::runnable_kernels()) {
    for (std::size_t n : {1u, 40u}) {
      const auto s = copies({0, 0, 0}, 1.0f, n);
      const Hit hit = k->intersect(s.view(), Ray{{0, 0, 10}, {0, 0, -1}, -kInf, kInf});
      EXPECT_EQ(hit.id, 0u);
      EXPECT_FLOAT_EQ(hit.t, 9.0f);
      // Looking away: roots -9 and -11 are both inside (-inf, inf).
      const Hit back = k->intersect(s.view(), Ray{{0, 0, 10}, {0, 0, 1}, -kInf, kInf});
      EXPECT_FLOAT_EQ(back.t, -11.0f) << test::name_of(k);
    }
  }
}

TEST(Degenerate, EmptyAndNullViews) {
  const SphereView empty{nullptr, nullptr, nullptr, nullptr, 0};
  for (const EntryTable* k : test::runnable_kernels()) {
    EXPECT_FALSE(k->intersect(empty, kTowardsOrigin).found());
    EXPECT_FALSE(k->occluded(empty, kTowardsOrigin));
  }
  EXPECT_FALSE(intersect(SphereSoA{}.view(), kTowardsOrigin).found());
}

TEST(Degenerate, SurfaceOfAMiss) {
  SphereSoA s;
  s.add({0, 0, 0}, 1.0f);
  const Ray ray{{0, 5, 10}, {0, 0, -1}, 0.0f, 3.0f};
  const Surface surf = surface(s.view(), ray, intersect(s.view(), ray));
  EXPECT_EQ(surf.normal, (Vec3{0, 0, 0}));
  EXPECT_EQ(surf.point, (Vec3{0, 5, 7}));
  EXPECT_FALSE(surf.front_face);
}

}  // namespace
}  // namespace sphray
