// Degenerate spheres and rays: a defined miss on every instruction set, never a crash.
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
  const float bad_radii[] = {0.0f, -1.0f, -kInf, kInf, kNaN};
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
