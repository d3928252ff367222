// SphereSoA: ids, storage, alignment and padding, and views.
#include <cstdint>

#include "test_support.hpp"

namespace sphray {
namespace {

TEST(SphereSoA, AddReturnsInsertionIndexAndViewRoundTrips) {
  SphereSoA s;
  for (std::uint32_t i = 0; i < 100; ++i) {
    const float f = static_cast<float>(i);
    EXPECT_EQ(s.add({f, 2 * f, 3 * f}, f + 0.5f), i);
  }
  EXPECT_EQ(s.size(), 100u);
  const SphereView v = s.view();
  ASSERT_EQ(v.count, 100u);
  for (std::uint32_t i = 0; i < 100; ++i) {
    const float f = static_cast<float>(i);
    EXPECT_EQ(v.cx[i], f);
    EXPECT_EQ(v.cy[i], 2 * f);
    EXPECT_EQ(v.cz[i], 3 * f);
    EXPECT_EQ(v.radius[i], f + 0.5f);
    EXPECT_EQ(s.center(i), (Vec3{f, 2 * f, 3 * f}));
  }
}

TEST(SphereSoA, ViewsAreAlignedAndPaddedWithNeverHitSpheres) {
  SphereSoA s;
  for (int n = 1; n <= 70; ++n) {
    s.add({1, 1, 1}, 1.0f);
    const SphereView v = s.view();
    for (const float* p : {v.cx, v.cy, v.cz, v.radius})
      EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p) % SphereSoA::kAlignment, 0u);
    EXPECT_EQ(v.padded_count % SphereSoA::kPadding, 0u);
    EXPECT_GE(v.padded_count, v.count);
    for (std::size_t i = v.count; i < v.padded_count; ++i)
      EXPECT_LE(v.radius[i], 0.0f);
  }
}

TEST(SphereSoA, SetReplacesAndChecksRange) {
  SphereSoA s;
  s.add({0, 0, 0}, 1.0f);
  s.add({0, 0, 5}, 1.0f);
  s.set(1, {7, 8, 9}, 2.0f);
  EXPECT_EQ(s.center(1), (Vec3{7, 8, 9}));
  EXPECT_EQ(s.radius(1), 2.0f);
  EXPECT_EQ(s.center(0), (Vec3{0, 0, 0}));
  EXPECT_THROW(s.set(2, {0, 0, 0}, 1.0f), std::out_of_range);
}

TEST(SphereSoA, ClearLeavesNothingToHit) {
  SphereSoA s;
  for (int i = 0; i < 40; ++i)
    s.add({0, 0, static_cast<float>(-i)}, 0.5f);
  s.clear();
  EXPECT_EQ(s.size(), 0u);
  EXPECT_EQ(s.view().count, 0u);
  // The old spheres must not survive as padding of a smaller scene.
  s.add({100, 100, 100}, 0.5f);
  const SphereView v = s.view();
  for (std::size_t i = 1; i < v.padded_count; ++i)
    EXPECT_EQ(v.radius[i], 0.0f);
  for (const EntryTable* k : test::runnable_kernels())
    EXPECT_FALSE(k->intersect(v, Ray{{0, 0, 1}, {0, 0, -1}}).found()) << test::name_of(k);
}

TEST(SphereSoA, ReserveKeepsContentsAndCopiesAreDeep) {
  SphereSoA s;
  s.add({1, 2, 3}, 4.0f);
  s.reserve(1000);
  EXPECT_GE(s.capacity(), 1000u);
  EXPECT_EQ(s.size(), 1u);
  EXPECT_EQ(s.center(0), (Vec3{1, 2, 3}));
  SphereSoA copy = s;
  copy.set(0, {9, 9, 9}, 1.0f);
  EXPECT_EQ(s.center(0), (Vec3{1, 2, 3}));
  EXPECT_EQ(copy.center(0), (Vec3{9, 9, 9}));
  SphereSoA moved = std::move(copy);
  EXPECT_EQ(moved.center(0), (Vec3{9, 9, 9}));
}

TEST(Vec3, Arithmetic) {
  const Vec3 a{1, 2, 3}, b{4, 5, 6};
  EXPECT_EQ(a + b, (Vec3{5, 7, 9}));
  EXPECT_EQ(b - a, (Vec3{3, 3, 3}));
  EXPECT_EQ(2.0f * a, (Vec3{2, 4, 6}));
  EXPECT_EQ(dot(a, b), 32.0f);
  EXPECT_EQ(cross(Vec3{1, 0, 0}, Vec3{0, 1, 0}), (Vec3{0, 0, 1}));
  EXPECT_FLOAT_EQ(length(Vec3{3, 4, 0}), 5.0f);
  EXPECT_FLOAT_EQ(length(normalize(Vec3{3, 4, 12})), 1.0f);
}

}  // namespace
}  // namespace sphray
