// Secondary rays from spawn(): rays leaving a hit outward never meet the sphere they leave, and
// rays leaving inward meet its far side at the distance a long-double reference gives, for
// radii from 1e-3 to 1e4 and centres up to 1e5 from the origin of coordinates, on every
// instruction set and on the BVH. The naive offsets (tmin = 0.001 from ray.at(t), as Ray Tracing
// in One Weekend does, and ray.at(t) + 1e-4 n) run on the same hit points beside it: they must
// fail somewhere in this range, or the range proves nothing. Rates go to docs/robustness.md.
#include <bit>
#include <cfloat>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <numbers>

#include "test_support.hpp"

namespace sphray {
namespace {

using Real = long double;

// Draws log-uniformly in [lo, hi].
float log_uniform(std::mt19937& rng, float lo, float hi) {
  return std::exp(test::uniform(rng, std::log(lo), std::log(hi)));
}

Vec3 unit_vector(std::mt19937& rng) {
  const float z = test::uniform(rng, -1.0f, 1.0f);
  const float phi = test::uniform(rng, 0.0f, 2.0f * std::numbers::pi_v<float>);
  const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

// A direction whose cosine with n is cosine (n unit): half the draws uniform in the hemisphere,
// half log-uniform down to 1e-6 so that grazing rays are well represented.
Vec3 direction_at_cosine(std::mt19937& rng, Vec3 n, float cosine) {
  Vec3 t;
  do {
    const Vec3 v = unit_vector(rng);
    t = v - dot(v, n) * n;
  } while (length_squared(t) < 1e-4f);
  t = normalize(t);
  const float sine = std::sqrt(std::max(0.0f, 1.0f - cosine * cosine));
  return cosine * n + sine * t;
}

float random_cosine(std::mt19937& rng, float lowest) {
  return rng() % 2 == 0 ? test::uniform(rng, lowest, 1.0f) : log_uniform(rng, lowest, 1.0f);
}

// The far root of |o + t d - c| = r in long double on the float inputs, if the line meets it.
std::optional<Real> far_root(Vec3 o, Vec3 d, Vec3 c, float r) {
  const Real g[3] = {Real(c.x) - o.x, Real(c.y) - o.y, Real(c.z) - o.z};
  const Real dv[3] = {d.x, d.y, d.z};
  Real a = 0, b = 0, gg = 0;
  for (int i = 0; i < 3; ++i) {
    a += dv[i] * dv[i];
    b += g[i] * dv[i];
    gg += g[i] * g[i];
  }
  const Real disc = b * b - a * (gg - Real(r) * r);
  if (disc < 0) return std::nullopt;
  return (b + std::sqrt(disc)) / a;
}

// One sphere and a ray from outside that hits it somewhere on its visible side.
struct Case {
  Vec3 center;
  float radius;
  Ray ray;
};

Case case_on(Vec3 center, float radius, std::mt19937& rng) {
  const float distance = radius * log_uniform(rng, 1.01f, 1e3f);
  const Vec3 origin = center + distance * unit_vector(rng);
  const Vec3 target = center + 0.999f * radius * unit_vector(rng);
  return {center, radius, Ray{origin, (target - origin) * log_uniform(rng, 0.1f, 10.0f)}};
}

Case random_case(std::mt19937& rng) {
  const float radius = log_uniform(rng, 1e-3f, 1e4f);
  const Vec3 center = unit_vector(rng) * log_uniform(rng, 1e-2f, 1e5f);
  return case_on(center, radius, rng);
}

// How each way of starting the next ray fared.
struct Tally {
  std::uint64_t outward = 0, outward_self_hits = 0;
  std::uint64_t inward = 0, inward_wrong = 0;
};

enum class Method { spawn, tmin_0001, offset_1e4 };

Ray next_ray(Method m, const Surface& s, const Ray& ray, const Hit& hit, Vec3 dir) {
  switch (m) {
    case Method::spawn:
      return spawn(s, dir);
    case Method::tmin_0001:
      return Ray{ray.at(hit.t), dir, 0.001f};
    case Method::offset_1e4: {
      const Vec3 side = dot(dir, s.normal) > 0.0f ? s.normal : -s.normal;
      return Ray{ray.at(hit.t) + 1e-4f * side, dir};
    }
  }
  return {};
}

// Where the test's rays go: hit(ray) on a scene holding the case's sphere as id.
using Tracer = std::function<Hit(const Ray&)>;

// The inward guarantee (docs/kernel.md) needs the chord to be longer than the offset: spheres
// at least 1e-4 of their centre's distance from the origin of coordinates across (smaller
// ones hold too few floats for a ray to start inside), rays at least 0.05 in cosine from the
// tangent plane (a refracted ray's is at least sqrt(1 - 1/ior^2), 0.75 for glass).
bool inward_guaranteed(const Case& c) {
  return c.radius >= 1e-4f * length(c.center);
}

// From the case's hit, one outward and one inward ray by each method.
void run_case(const Case& c, std::uint32_t id, SphereView view, const Tracer& trace,
              std::mt19937& rng, Tally (&tally)[3], std::string* first_failure) {
  const Hit hit = trace(c.ray);
  if (hit.id != id) return;  // another sphere in front (BVH scenes), or a grazing miss
  const Surface s = surface(view, c.ray, hit);
  const Vec3 out = direction_at_cosine(rng, s.normal, random_cosine(rng, 1e-6f));
  const Vec3 in = direction_at_cosine(rng, -s.normal, random_cosine(rng, 0.05f));
  for (int m = 0; m < 3; ++m) {
    Tally& t = tally[m];
    if (dot(out, s.normal) > 0.0f) {
      const Ray r = next_ray(static_cast<Method>(m), s, c.ray, hit, out);
      ++t.outward;
      if (trace(r).id == id) {
        ++t.outward_self_hits;
        if (m == 0 && first_failure->empty()) {
          *first_failure = "outward self-hit: radius " + std::to_string(c.radius) +
                           " centre distance " + std::to_string(length(c.center)) + " cosine " +
                           std::to_string(dot(out, s.normal));
        }
      }
    }
    if (dot(in, s.normal) < 0.0f && inward_guaranteed(c)) {
      const Ray r = next_ray(static_cast<Method>(m), s, c.ray, hit, in);
      ++t.inward;
      const Hit h = trace(r);
      const auto ref = far_root(r.origin, r.dir, c.center, c.radius);
      bool right = h.id == id && ref.has_value();
      if (right) {
        const Real dir_len = std::sqrt(Real(dot(r.dir, r.dir)));
        const Real error = std::abs(Real(h.t) - *ref) * dir_len;
        right = error <= 1e-5L * std::max(*ref * dir_len, Real(c.radius));
      }
      if (!right) {
        ++t.inward_wrong;
        if (m == 0 && first_failure->empty()) {
          *first_failure = "inward: radius " + std::to_string(c.radius) + " centre distance " +
                           std::to_string(length(c.center)) + " got id " + std::to_string(h.id) +
                           " t " + std::to_string(h.t) + " reference " +
                           (ref ? std::to_string(double(*ref)) : "none");
        }
      }
    }
  }
}

void report(const std::string& where, const Tally (&tally)[3]) {
  const char* names[3] = {"spawn", "tmin=0.001", "p+1e-4n"};
  for (int m = 0; m < 3; ++m) {
    const Tally& t = tally[m];
    std::printf("%s %-10s outward self-hits %" PRIu64 " / %" PRIu64
                " (%.4f%%), inward wrong %" PRIu64 " / %" PRIu64 " (%.4f%%)\n",
                where.c_str(), names[m], t.outward_self_hits, t.outward,
                100.0 * double(t.outward_self_hits) / double(std::max<std::uint64_t>(t.outward, 1)),
                t.inward_wrong, t.inward,
                100.0 * double(t.inward_wrong) / double(std::max<std::uint64_t>(t.inward, 1)));
  }
}

void expect_spawn_exact_and_naive_wrong(const std::string& where, const Tally (&tally)[3],
                                        std::uint64_t cases, const std::string& first_failure) {
  report(where, tally);
  EXPECT_GT(tally[0].outward, cases / 2) << where;
  EXPECT_GT(tally[0].inward, cases / 4) << where;
  EXPECT_EQ(tally[0].outward_self_hits, 0u) << where << ": " << first_failure;
  EXPECT_EQ(tally[0].inward_wrong, 0u) << where << ": " << first_failure;
  // The naive offsets must go wrong in this range, or it is too easy to show anything.
  EXPECT_GT(tally[1].outward_self_hits + tally[1].inward_wrong, 0u) << where;
  EXPECT_GT(tally[2].outward_self_hits + tally[2].inward_wrong, 0u) << where;
}

class SpawnPerIsa : public ::testing::TestWithParam<Isa> {};

TEST_P(SpawnPerIsa, OutwardNeverSelfHitsInwardFindsTheFarSide) {
  const EntryTable* k = find_entries(GetParam());
  ASSERT_NE(k, nullptr);
  std::mt19937 rng(1200 + static_cast<unsigned>(GetParam()));
  const std::size_t cases = test::scaled(1000000);
  Tally tally[3];
  std::string first_failure;
  // The sphere sits among 39 never-hit slots so that every kernel runs its SIMD batches (a view
  // of one sphere goes to the scalar loop).
  test::LooseSpheres s(3);
  for (int i = 0; i < 40; ++i)
    s.add({0, 0, 0}, 0.0f);
  constexpr std::uint32_t kId = 21;
  for (std::size_t i = 0; i < cases; ++i) {
    const Case c = random_case(rng);
    s.storage[0][s.offset + kId] = c.center.x;
    s.storage[1][s.offset + kId] = c.center.y;
    s.storage[2][s.offset + kId] = c.center.z;
    s.storage[3][s.offset + kId] = c.radius;
    const SphereView view = s.view();
    run_case(
        c, kId, view, [&](const Ray& r) { return k->intersect(view, r); }, rng, tally,
        &first_failure);
  }
  expect_spawn_exact_and_naive_wrong(test::name_of(k), tally, cases, first_failure);
}

INSTANTIATE_TEST_SUITE_P(EveryRunnableIsa, SpawnPerIsa, ::testing::ValuesIn(supported_isas()),
                         [](const auto& info) {
                           std::string name(isa_name(info.param));
                           std::erase(name, '.');
                           return name;
                         });

// front_face says which side the ray came from, not the sign of dot(dir, normal): rays from
// outside that graze a large sphere (the book's ground, radius 1000, seen from a camera 1.2
// above it) are front faces, every one, although for a grazing ray that dot product is below
// the normal's rounding; rays from inside are back faces. The grazing rays aim at angles
// log-uniform from 1e-9 to 1e-3 radians inside the tangent cone (the closest to the cone, whose
// hits float puts anywhere along the chord, are where the sign of the dot product fails).
TEST_P(SpawnPerIsa, FrontFaceIsTheSideTheRayCameFrom) {
  const EntryTable* k = find_entries(GetParam());
  ASSERT_NE(k, nullptr);
  test::LooseSpheres s(3);
  for (int i = 0; i < 40; ++i)
    s.add({0, 0, 0}, 0.0f);
  constexpr std::uint32_t kId = 21;
  const Vec3 center{0, -1000, 0};
  constexpr float kRadius = 1000.0f;
  s.storage[1][s.offset + kId] = center.y;
  s.storage[3][s.offset + kId] = kRadius;
  const SphereView view = s.view();
  std::mt19937 rng(3200 + static_cast<unsigned>(GetParam()));

  // The tangent cone from the camera: axis a toward the centre, half-angle asin(r / |c - o|).
  const Vec3 origin{0, 1.2f, 5};
  const double gx = center.x - origin.x, gy = center.y - origin.y, gz = center.z - origin.z;
  const double distance = std::sqrt(gx * gx + gy * gy + gz * gz);
  const double ax = gx / distance, ay = gy / distance, az = gz / distance;
  const double ux = 1, uy = 0, uz = 0;  // a unit vector across the axis (a has no x)
  const double vx = ay * uz - az * uy, vy = az * ux - ax * uz, vz = ax * uy - ay * ux;
  const double half_angle = std::asin(double(kRadius) / distance);
  const std::size_t rays = test::scaled(1000000);
  std::size_t grazing_hits = 0, back_faces = 0;
  for (std::size_t i = 0; i < rays; ++i) {
    const double phi = test::uniform(rng, 0.0f, 2.0f * std::numbers::pi_v<float>);
    const double angle = half_angle - double(log_uniform(rng, 1e-9f, 1e-3f));
    const double across = std::sin(angle), along = std::cos(angle);
    const double cx = std::cos(phi) * across, cy = std::sin(phi) * across;
    const Vec3 dir{static_cast<float>(along * ax + cx * ux + cy * vx),
                   static_cast<float>(along * ay + cx * uy + cy * vy),
                   static_cast<float>(along * az + cx * uz + cy * vz)};
    const Ray ray{origin, dir};
    const Hit hit = k->intersect(view, ray);
    if (hit.id != kId) continue;  // float's direction missed the cone
    ++grazing_hits;
    back_faces += surface(view, ray, hit).front_face ? 0 : 1;
  }
  EXPECT_GT(grazing_hits, rays / 2);
  EXPECT_EQ(back_faces, 0u) << "of " << grazing_hits << " grazing hits from outside";

  // From inside: origins up to 10 below the top, any direction (every one meets the sphere).
  std::size_t front_faces = 0;
  for (std::size_t i = 0; i < rays / 10; ++i) {
    const Ray ray{{0, -log_uniform(rng, 1e-3f, 10.0f), 0}, unit_vector(rng)};
    const Hit hit = k->intersect(view, ray);
    ASSERT_EQ(hit.id, kId);
    front_faces += surface(view, ray, hit).front_face ? 1 : 0;
  }
  EXPECT_EQ(front_faces, 0u);
}

// Spheres of every scale in one scene, none overlapping, queried through the BVH's stream.
TEST(SpawnBvh, OutwardNeverSelfHitsInwardFindsTheFarSide) {
  std::mt19937 rng(77);
  SphereSoA spheres;
  std::vector<Case> shapes;
  while (shapes.size() < 2000) {
    const Case c = random_case(rng);
    bool overlaps = false;
    for (const Case& o : shapes)
      overlaps = overlaps || length(o.center - c.center) < 1.01f * (o.radius + c.radius);
    if (overlaps) continue;
    shapes.push_back(c);
    spheres.add(c.center, c.radius);
  }
  const SphereBVH bvh(spheres.view());
  const Tracer trace = [&](const Ray& r) {
    Hit h;
    intersect(bvh, std::span(&r, 1), std::span(&h, 1));
    EXPECT_EQ(h.id, intersect(bvh, r).id);
    return h;
  };
  const std::size_t rounds = test::scaled(250);
  Tally tally[3];
  std::string first_failure;
  for (std::size_t round = 0; round < rounds; ++round) {
    for (std::uint32_t id = 0; id < shapes.size(); ++id) {
      const Case c = case_on(shapes[id].center, shapes[id].radius, rng);
      run_case(c, id, spheres.view(), trace, rng, tally, &first_failure);
    }
  }
  expect_spawn_exact_and_naive_wrong("bvh", tally, rounds * shapes.size() / 2, first_failure);
}

TEST(Spawn, MissGivesTheRayFromThePoint) {
  const Surface s{{1, 2, 3}, {0, 0, 0}, false};
  const Ray r = spawn(s, {0, 1, 0});
  EXPECT_EQ(r.origin, (Vec3{1, 2, 3}));
  EXPECT_EQ(r.dir, (Vec3{0, 1, 0}));
  EXPECT_EQ(r.tmin, 0.0f);
  EXPECT_EQ(r.tmax, INFINITY);
}

TEST(Spawn, OffsetIsToTheSideTheDirectionLeavesBy) {
  SphereSoA s;
  s.add({0, 0, -10}, 2.0f);
  const Ray ray{{0, 0, 0}, {0, 0, -1}};
  const Surface surf = surface(s.view(), ray, intersect(s.view(), ray));
  ASSERT_EQ(surf.normal, (Vec3{0, 0, 1}));
  const Vec3 out = offset_origin(surf, {0, 1, 1});
  const Vec3 in = offset_origin(surf, {0, 1, -1});
  EXPECT_GT(out.z, surf.point.z);
  EXPECT_LT(in.z, surf.point.z);
  // A computed bound, not a constant: about 1e-6 of the scene's scale here (12 units), far
  // below the 1e-4 an ad-hoc offset would add.
  EXPECT_LT(out.z - surf.point.z, 2e-5f);
  EXPECT_LT(surf.point.z - in.z, 2e-5f);
}

// offset_origin() moves the point by d along the normal, then one float further the way it
// moved (pbrt-v4's NextFloatUp/Down). That step is bit arithmetic of its own: here it is checked
// against std::nextafter on the values where stepping bits is easy to get wrong: zeros of both
// signs, denormals, the largest finite float and infinities, moving either way.
TEST(Spawn, RoundingAwayAgreesWithNextafter) {
  const float values[] = {0.0f,  -0.0f,  0x1p-149f, -0x1p-149f, 0x1p-126f, -0x1p-126f, 1.0f,
                          -1.0f, 3.5e7f, -3.5e7f,   FLT_MAX,    -FLT_MAX,  INFINITY,   -INFINITY};
  for (float x : values) {
    for (float side : {1.0f, -1.0f}) {
      // Normal +z and an error bound of the smallest denormal along z only: d is that denormal,
      // x and y do not move (an offset of zero is not stepped), z moves by side * d.
      const Surface surf{{x, x, x}, {0, 0, 1}, true, {0, 0, 0x1p-149f}};
      const Vec3 o = offset_origin(surf, {0, 0, side});
      const float moved = x + side * 0x1p-149f;
      const float expected = std::nextafter(moved, side * INFINITY);
      const auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f); };
      EXPECT_EQ(bits(o.z), bits(expected)) << "x = " << x << ", side = " << side;
      const float unmoved = x + std::copysign(0.0f, side);  // x plus a zero offset of side's sign
      EXPECT_EQ(bits(o.x), bits(unmoved)) << "x = " << x << ", side = " << side;
      EXPECT_EQ(bits(o.y), bits(unmoved)) << "x = " << x << ", side = " << side;
    }
  }
}

}  // namespace
}  // namespace sphray
