// Cases worked by hand, on every instruction set. Each scene is tested twice: alone (below the
// scalar-path threshold) and hidden among never-hit spheres at every lane position of a batch,
// so the SIMD path, its masks and its tail see it too.
#include <cmath>

#include "test_support.hpp"

namespace sphray {
namespace {

using test::runnable_kernels;

// The scene {centre, r} placed at position `slot` among `total` spheres; the others are far
// away behind the ray origin at z = +1000, so they are never hit by rays going towards -z.
test::LooseSpheres hidden_among(Vec3 center, float r, std::size_t slot, std::size_t total) {
  test::LooseSpheres s;
  for (std::size_t i = 0; i < total; ++i) {
    if (i == slot)
      s.add(center, r);
    else
      s.add({static_cast<float>(i), 0.0f, 1000.0f}, 0.5f);
  }
  return s;
}

// Runs check(kernel, view, id_of_the_sphere) for every kernel and placement.
template <class Check>
void for_every_placement(Vec3 center, float r, Check check) {
  for (const EntryTable* k : runnable_kernels()) {
    for (std::size_t total : {1u, 20u, 37u}) {
      for (std::size_t slot = 0; slot < total; slot += (total > 1 ? 3 : 1)) {
        const auto s = hidden_among(center, r, slot, total);
        SCOPED_TRACE(test::name_of(k) + " total " + std::to_string(total) + " slot " +
                     std::to_string(slot));
        check(*k, s.view(), static_cast<std::uint32_t>(slot));
      }
    }
  }
}

// Ray Tracing in One Weekend, ch. 5: the red sphere at (0,0,-1), r 0.5, camera at the origin.
const Vec3 kCenter{0.0f, 0.0f, -1.0f};
constexpr float kRadius = 0.5f;

TEST(WorkedCases, CentreRayHitsAtHalf) {
  // |(0,0,-t) - (0,0,-1)| = 0.5 gives t = 0.5 and t = 1.5; the near root is taken.
  for_every_placement(kCenter, kRadius, [](const EntryTable& k, SphereView v, std::uint32_t id) {
    const Ray ray{{0, 0, 0}, {0, 0, -1}};
    const Hit hit = k.intersect(v, ray);
    EXPECT_EQ(hit.id, id);
    EXPECT_FLOAT_EQ(hit.t, 0.5f);
    EXPECT_TRUE(k.occluded(v, ray));
    const Surface s = surface(v, ray, hit);
    EXPECT_FLOAT_EQ(s.normal.z, 1.0f);
    EXPECT_FLOAT_EQ(s.normal.x, 0.0f);
    EXPECT_FLOAT_EQ(s.point.z, -0.5f);
    EXPECT_TRUE(s.front_face);
  });
}

TEST(WorkedCases, CornerRaysOfTheBookCameraMiss) {
  // Viewport 2 high, 16:9, focal length 1: the corners are (+-16/9, +-1, -1). Closest approach of
  // such a ray to the centre: sqrt(1 - 1/(1 + 1 + 256/81)) = 0.898 > 0.5.
  for_every_placement(kCenter, kRadius, [](const EntryTable& k, SphereView v, std::uint32_t) {
    for (float sx : {-1.0f, 1.0f})
      for (float sy : {-1.0f, 1.0f}) {
        const Ray ray{{0, 0, 0}, {sx * 16.0f / 9.0f, sy, -1.0f}};
        const Hit hit = k.intersect(v, ray);
        EXPECT_FALSE(hit.found());
        EXPECT_EQ(hit.t, ray.tmax);
        EXPECT_FALSE(k.occluded(v, ray));
      }
  });
}

TEST(WorkedCases, SphereBehindTheCameraIsNotHit) {
  // Moved to z = +1, both roots are negative (t = -0.5 and -1.5 along (0,0,-1)).
  for_every_placement({0, 0, 1}, kRadius, [](const EntryTable& k, SphereView v, std::uint32_t) {
    const Ray ray{{0, 0, 0}, {0, 0, -1}};
    EXPECT_FALSE(k.intersect(v, ray).found());
    EXPECT_FALSE(k.occluded(v, ray));
  });
}

TEST(WorkedCases, TangentRays) {
  // A ray at x = 0.5 exactly touches the sphere at (0.5, 0, -1): the discriminant is exactly 0
  // and the double root t = 1 counts as a hit. Slightly outside misses; slightly inside hits.
  for_every_placement(kCenter, kRadius, [](const EntryTable& k, SphereView v, std::uint32_t id) {
    const Hit touch = k.intersect(v, Ray{{0.5f, 0, 0}, {0, 0, -1}});
    EXPECT_EQ(touch.id, id);
    EXPECT_FLOAT_EQ(touch.t, 1.0f);
    EXPECT_FALSE(k.intersect(v, Ray{{0.5001f, 0, 0}, {0, 0, -1}}).found());
    // x = 0.4999: t = 1 - sqrt(0.25 - 0.4999^2) = 1 - 0.0099995.
    const Hit inside = k.intersect(v, Ray{{0.4999f, 0, 0}, {0, 0, -1}});
    EXPECT_EQ(inside.id, id);
    EXPECT_NEAR(inside.t, 1.0f - std::sqrt(0.25f - 0.4999f * 0.4999f), 2e-5f);
  });
}

TEST(WorkedCases, RayFromInsideHitsTheFarSide) {
  // From the centre along -z the roots are -0.5 and +0.5: the far one, seen from inside.
  for_every_placement(kCenter, kRadius, [](const EntryTable& k, SphereView v, std::uint32_t id) {
    const Ray ray{kCenter, {0, 0, -1}};
    const Hit hit = k.intersect(v, ray);
    EXPECT_EQ(hit.id, id);
    EXPECT_FLOAT_EQ(hit.t, 0.5f);
    const Surface s = surface(v, ray, hit);
    EXPECT_FLOAT_EQ(s.normal.z, -1.0f);  // outward, not towards the ray
    EXPECT_FALSE(s.front_face);
  });
}

TEST(WorkedCases, DirectionLengthScalesT) {
  // dir = (0,0,-4): the same points, at t = 0.5 / 4.
  for_every_placement(kCenter, kRadius, [](const EntryTable& k, SphereView v, std::uint32_t id) {
    const Hit hit = k.intersect(v, Ray{{0, 0, 0}, {0, 0, -4}});
    EXPECT_EQ(hit.id, id);
    EXPECT_FLOAT_EQ(hit.t, 0.125f);
  });
}

TEST(WorkedCases, IntervalIsOpenAtBothRoots) {
  // Roots at t = 0.5 and 1.5 along (0,0,-1) from the origin.
  struct Case {
    float tmin, tmax;
    bool hit;
    float t;
  };
  const Case cases[] = {
      {0.0f, INFINITY, true, 0.5f}, {0.4999f, 10.0f, true, 0.5f}, {0.5f, 10.0f, true, 1.5f},
      {0.5001f, 10.0f, true, 1.5f}, {1.0f, 2.0f, true, 1.5f},     {1.4999f, 2.0f, true, 1.5f},
      {1.5f, 10.0f, false, 0.0f},   {0.0f, 0.5f, false, 0.0f},    {0.0f, 0.5001f, true, 0.5f},
      {0.6f, 1.5f, false, 0.0f},    {0.6f, 1.5001f, true, 1.5f},  {-10.0f, 0.4f, false, 0.0f},
  };
  for_every_placement(kCenter, kRadius, [&](const EntryTable& k, SphereView v, std::uint32_t id) {
    for (const Case& c : cases) {
      SCOPED_TRACE("tmin " + std::to_string(c.tmin) + " tmax " + std::to_string(c.tmax));
      const Ray ray{{0, 0, 0}, {0, 0, -1}, c.tmin, c.tmax};
      const Hit hit = k.intersect(v, ray);
      EXPECT_EQ(hit.found(), c.hit);
      EXPECT_EQ(k.occluded(v, ray), c.hit);
      if (c.hit) {
        EXPECT_EQ(hit.id, id);
        EXPECT_FLOAT_EQ(hit.t, c.t);
      } else {
        EXPECT_EQ(hit.t, c.tmax);
      }
    }
  });
}

TEST(WorkedCases, ClosestOfSeveralAndLowerIdOnTies) {
  // Spheres along -z at z = -3, -2 (twice, ids 1 and 2... placed at every distance apart), -5:
  // the ray from the origin hits z = -2 + 0.5 first; the two identical spheres tie.
  for (const EntryTable* k : runnable_kernels()) {
    for (std::size_t gap : {1u, 3u, 4u, 8u, 16u, 17u}) {
      test::LooseSpheres s;
      s.add({0, 0, -3}, 0.5f);
      for (std::size_t i = 0; i < 40; ++i) {
        if (i == 2 || i == 2 + gap)
          s.add({0, 0, -2}, 0.5f);
        else
          s.add({0, 0, -5}, 0.5f);
      }
      SCOPED_TRACE(test::name_of(k) + " gap " + std::to_string(gap));
      const Hit hit = k->intersect(s.view(), Ray{{0, 0, 0}, {0, 0, -1}});
      EXPECT_EQ(hit.id, 3u);  // s.add order: id 0 is z=-3, then ids 1..40; i == 2 is id 3
      EXPECT_FLOAT_EQ(hit.t, 1.5f);
    }
  }
}

}  // namespace
}  // namespace sphray
