// The materials' scattering against Snell's law, the mirror law and Fresnel's normal-incidence
// reflectance, each written out here from the physics rather than from the renderer's helpers.
#include <gtest/gtest.h>

#include <cmath>

#include "sphray/render/material.hpp"

namespace sphray::render {
namespace {

Material glass(float ior) {
  return {MaterialKind::dielectric, {1, 1, 1}, 0.0f, ior};
}

// A surface at the origin with outward normal +y, hit from outside (front) or from inside.
Surface surface_up(bool front_face) {
  return {{0, 0, 0}, {0, 1, 0}, front_face};
}

Vec3 unit(Vec3 v) {
  return v / std::sqrt(dot(v, v));
}

void expect_direction(Vec3 actual, Vec3 expected, float tolerance = 1e-6f) {
  const Vec3 a = unit(actual);
  const Vec3 e = unit(expected);
  EXPECT_NEAR(a.x, e.x, tolerance);
  EXPECT_NEAR(a.y, e.y, tolerance);
  EXPECT_NEAR(a.z, e.z, tolerance);
}

TEST(Dielectric, IndexOneLeavesEveryRayUndeflected) {
  const Material m = glass(1.0f);
  for (bool front : {true, false}) {
    for (float sine : {0.0f, 0.3f, 0.7f, 0.95f, 0.999f}) {
      const float cosine = std::sqrt(1.0f - sine * sine);
      // Towards the surface from the side front_face names.
      const Vec3 incoming{sine, front ? -cosine : cosine, 0.25f * sine};
      for (std::uint32_t draw = 0; draw < 50; ++draw) {
        PathRandom random(7, draw, 0);
        const auto s = scatter(m, incoming, surface_up(front), random);
        ASSERT_TRUE(s.has_value());
        EXPECT_EQ(s->attenuation, (Vec3{1, 1, 1}));
        expect_direction(s->direction, incoming);
      }
    }
  }
}

// Inside glass of index 1.5 (front_face false: the ray leaves through the surface), the
// critical angle is asin(1 / 1.5). Past it every draw reflects, by the mirror law; short of it
// the ray refracts (Schlick's reflectance is near 4% there) with sin(out) = 1.5 sin(in).
TEST(Dielectric, TotalInternalReflectionWhereSnellSays) {
  const Material m = glass(1.5f);
  const float critical = 1.0f / 1.5f;
  const float past = critical * 1.001f;
  const Vec3 beyond{past, std::sqrt(1.0f - past * past), 0};
  for (std::uint32_t draw = 0; draw < 200; ++draw) {
    PathRandom random(3, draw, 0);
    const auto s = scatter(m, beyond, surface_up(false), random);
    ASSERT_TRUE(s.has_value());
    expect_direction(s->direction, {beyond.x, -beyond.y, 0});
  }
  const float short_of = critical * 0.999f;
  const Vec3 within{short_of, std::sqrt(1.0f - short_of * short_of), 0};
  const double out_sine = 1.5 * short_of;
  const Vec3 snell{static_cast<float>(out_sine),
                   static_cast<float>(std::sqrt(1 - out_sine * out_sine)), 0};
  int refracted = 0;
  for (std::uint32_t draw = 0; draw < 200; ++draw) {
    PathRandom random(3, draw, 0);
    const auto s = scatter(m, within, surface_up(false), random);
    ASSERT_TRUE(s.has_value());
    if (s->direction.y > 0.0f) {
      ++refracted;
      expect_direction(s->direction, snell, 2e-3f);  // near grazing: float's sqrt(1 - x^2)
    } else {
      expect_direction(s->direction, {within.x, -within.y, 0});
    }
  }
  EXPECT_GT(refracted, 180);
}

// Fresnel at normal incidence: ((n - 1) / (n + 1))^2 = 0.04 for n = 1.5. Over N draws the
// reflected fraction has standard deviation sqrt(0.04 * 0.96 / N) = 0.00196 for N = 10000; the
// bound is five of them.
TEST(Dielectric, ReflectsFourPercentAtNormalIncidence) {
  const Material m = glass(1.5f);
  constexpr int kDraws = 10000;
  int reflected = 0;
  for (std::uint32_t draw = 0; draw < kDraws; ++draw) {
    PathRandom random(11, draw, 0);
    const auto s = scatter(m, {0, -1, 0}, surface_up(true), random);
    ASSERT_TRUE(s.has_value());
    if (s->direction.y > 0.0f) {
      ++reflected;
      expect_direction(s->direction, {0, 1, 0});
    } else {
      expect_direction(s->direction, {0, -1, 0});
    }
  }
  EXPECT_NEAR(static_cast<double>(reflected) / kDraws, 0.04, 5 * 0.00196);
}

TEST(Metal, MirrorWithoutFuzzReflectsByTheMirrorLaw) {
  const Material m{MaterialKind::metal, {0.9f, 0.8f, 0.7f}, 0.0f};
  PathRandom random(1, 2, 3);
  const auto s = scatter(m, {3, -4, 1}, surface_up(true), random);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->attenuation, (Vec3{0.9f, 0.8f, 0.7f}));
  expect_direction(s->direction, {3, 4, 1});
}

// Fuzz moves the mirror direction by at most fuzz (a point in the unit ball times fuzz, added
// to the unit mirror direction); a grazing reflection fuzzed below the surface is absorbed.
TEST(Metal, FuzzStaysWithinItsBallAndBelowTheSurfaceIsAbsorbed) {
  const Material m{MaterialKind::metal, {1, 1, 1}, 0.3f};
  const Vec3 mirror = unit({1, 1, 0});
  int absorbed = 0;
  for (std::uint32_t draw = 0; draw < 1000; ++draw) {
    PathRandom random(5, draw, 0);
    const auto s = scatter(m, {1, -1, 0}, surface_up(true), random);
    ASSERT_TRUE(s.has_value());
    EXPECT_LE(length(s->direction - mirror), 0.3f + 1e-6f);
  }
  for (std::uint32_t draw = 0; draw < 1000; ++draw) {
    PathRandom random(5, draw, 0);
    const auto s = scatter(m, {1, -0.01f, 0}, surface_up(true), random);
    if (!s) {
      ++absorbed;
    } else {
      EXPECT_GT(s->direction.y, 0.0f);
    }
  }
  EXPECT_GT(absorbed, 100);  // about half: the ball straddles the surface there
}

TEST(Lambertian, ScattersIntoTheHemisphereOfTheSideHit) {
  const Material m{MaterialKind::lambertian, {0.5f, 0.25f, 1}};
  for (bool front : {true, false}) {
    for (std::uint32_t draw = 0; draw < 1000; ++draw) {
      PathRandom random(9, draw, 0);
      const auto s = scatter(m, {0.3f, front ? -1.0f : 1.0f, 0}, surface_up(front), random);
      ASSERT_TRUE(s.has_value());
      EXPECT_EQ(s->attenuation, (Vec3{0.5f, 0.25f, 1}));
      // n + a unit vector: at or above the tangent plane of the side the ray came from.
      EXPECT_GE(front ? s->direction.y : -s->direction.y, 0.0f);
    }
  }
}

TEST(MaterialKinds, NamesRoundTrip) {
  for (MaterialKind k : {MaterialKind::lambertian, MaterialKind::metal, MaterialKind::dielectric})
    EXPECT_EQ(parse_material_kind(material_kind_name(k)), k);
  EXPECT_FALSE(parse_material_kind("glass"));
}

}  // namespace
}  // namespace sphray::render
