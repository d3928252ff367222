// The precision targets of the kernel, against the same mathematics carried out in long double
// on the same float inputs: origins from 1e-3 to 1e4 radii from the surface, inside and outside,
// spheres far from the origin of coordinates, directions of any length.
#include <cmath>
#include <optional>

#include "test_support.hpp"

namespace sphray {
namespace {

using Real = long double;

struct Reference {
  std::optional<Real> t;  // hit parameter with tmin = 0, tmax = inf
  Real approach_margin;   // |closest approach to the centre - r| / r
};

// Exact-enough roots of |o + t d - c| = r in long double (64-bit mantissa), textbook form: with
// 40 more bits than float, the cancellation that float must avoid is harmless here.
Reference reference(Vec3 c, float r, const Ray& ray) {
  const Real gx = Real(c.x) - ray.origin.x, gy = Real(c.y) - ray.origin.y,
             gz = Real(c.z) - ray.origin.z;
  const Real dx = ray.dir.x, dy = ray.dir.y, dz = ray.dir.z;
  const Real a = dx * dx + dy * dy + dz * dz;
  const Real b = gx * dx + gy * dy + gz * dz;
  const Real g2 = gx * gx + gy * gy + gz * gz;
  const Real approach2 = g2 - b * b / a;
  const Real rr = Real(r);
  Reference ref{std::nullopt, std::abs(std::sqrt(std::max(approach2, Real(0))) - rr) / rr};
  const Real disc = b * b - a * (g2 - rr * rr);
  if (disc < 0) return ref;
  const Real s = std::sqrt(disc);
  const Real t0 = (b - s) / a, t1 = (b + s) / a;
  if (t0 > 0)
    ref.t = t0;
  else if (t1 > 0)
    ref.t = t1;
  return ref;
}

// Log-uniform in [lo, hi].
float log_uniform(std::mt19937& rng, float lo, float hi) {
  return std::exp(test::uniform(rng, std::log(lo), std::log(hi)));
}

struct Case {
  Vec3 center;
  float radius;
  Ray ray;
};

// An origin at a chosen distance from the surface (inside: up to one radius), aimed at a random
// point within 1.5 radii of the centre, so hits, misses and grazes all occur.
Case random_case(std::mt19937& rng) {
  Case k;
  k.radius = log_uniform(rng, 1e-2f, 1e3f);
  k.center = test::random_in_box(rng, 1e3f);
  const bool inside = rng() % 4 == 0;
  const float gap = inside ? log_uniform(rng, 1e-3f, 0.999f) : log_uniform(rng, 1e-3f, 1e4f);
  const float dist = k.radius * (inside ? 1.0f - gap : 1.0f + gap);
  const Vec3 origin = k.center + dist * test::unit_vector(rng);
  const Vec3 target =
      k.center + 1.5f * k.radius * test::uniform(rng, 0.0f, 1.0f) * test::unit_vector(rng);
  const float scale = log_uniform(rng, 1e-2f, 1e2f);
  k.ray = Ray{origin, normalize(target - origin) * scale};
  return k;
}

TEST(Precision, HitMissAndDistanceAgainstLongDouble) {
  const int case_count = static_cast<int>(test::scaled(200000));
  std::mt19937 rng(1234);
  std::vector<Case> cases;
  for (int i = 0; i < case_count; ++i)
    cases.push_back(random_case(rng));

  for (const EntryTable* k : test::runnable_kernels()) {
    int checked_hits = 0, decided = 0;
    for (const Case& c : cases) {
      // 40 spheres: the tested one in lane 5, the rest never hit, so the SIMD path runs.
      test::LooseSpheres s;
      for (int i = 0; i < 40; ++i)
        s.add(i == 5 ? c.center : Vec3{0, 0, 0}, i == 5 ? c.radius : 0.0f);
      const Hit hit = k->intersect(s.view(), c.ray);
      const Reference ref = reference(c.center, c.radius, c.ray);
      if (ref.approach_margin <= 1e-3L) continue;  // too close to tangent to demand agreement
      ++decided;
      ASSERT_EQ(hit.found(), ref.t.has_value())
          << test::name_of(k) << ": origin gap " << length(c.ray.origin - c.center) / c.radius - 1
          << " radius " << c.radius;
      if (!ref.t) continue;
      const Real dir_len = std::sqrt(Real(dot(c.ray.dir, c.ray.dir)));
      const Real error = std::abs(Real(hit.t) - *ref.t) * dir_len;
      const Real bound = 1e-5L * std::max(*ref.t * dir_len, Real(c.radius));
      ASSERT_LE(error, bound) << test::name_of(k) << ": t " << hit.t << " reference "
                              << double(*ref.t) << " radius " << c.radius;
      ++checked_hits;
    }
    // The generator must really produce both outcomes, or the test proves little.
    EXPECT_GT(checked_hits, case_count / 5) << test::name_of(k);
    EXPECT_GT(decided - checked_hits, case_count / 10) << test::name_of(k);
  }
}

TEST(Precision, SurfacePointIsOnTheSphereAndNormalIsUnit) {
  std::mt19937 rng(99);
  for (int i = 0; i < 20000; ++i) {
    const Case c = random_case(rng);
    SphereSoA s;
    s.add(c.center, c.radius);
    const Hit hit = intersect(s.view(), c.ray);
    if (!hit.found()) continue;
    const Surface surf = surface(s.view(), c.ray, hit);
    ASSERT_NEAR(length(surf.normal), 1.0f, 1e-6f);
    ASSERT_NEAR(length(surf.point - c.center), c.radius, 1e-6f * (c.radius + length(c.center)));
    const bool outside = length(c.ray.origin - c.center) > c.radius;
    // Seen from outside the ray meets the front face, from inside the back face; origins within
    // rounding of the surface may go either way.
    if (std::abs(length(c.ray.origin - c.center) / c.radius - 1) > 1e-4f) {
      ASSERT_EQ(surf.front_face, outside);
    }
  }
}

}  // namespace
}  // namespace sphray
