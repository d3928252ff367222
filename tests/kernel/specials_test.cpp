// Special values in every field of spheres and rays (denormals, tiny, huge, FLT_MAX, infinities,
// NaN, signed zeros), on every instruction set: brute force against the tree, each query
// against the others, and every hit on a sphere the contract calls valid (issue 30: a sphere
// of denormal radius was hit 8e6 radii away by brute force and the AVX2 tree, and missed by
// the scalar and SSE4.2 trees).
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>

#include "test_support.hpp"

namespace sphray {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

std::string hex(float x) {
  char text[32];
  std::snprintf(text, sizeof text, "%a", static_cast<double>(x));
  return text;
}

std::string describe(const Ray& r) {
  return "ray o (" + hex(r.origin.x) + ", " + hex(r.origin.y) + ", " + hex(r.origin.z) + ") d (" +
         hex(r.dir.x) + ", " + hex(r.dir.y) + ", " + hex(r.dir.z) + ") [" + hex(r.tmin) + ", " +
         hex(r.tmax) + ")";
}

// A special value: magnitudes at the edges of float's range and of the contract's (squares
// that underflow or overflow), with either sign, or NaN.
float special(std::mt19937& rng) {
  static const float kMagnitudes[] = {0.0f,
                                      std::numeric_limits<float>::denorm_min(),
                                      1e-45f,
                                      1e-40f,
                                      1.17e-38f,
                                      FLT_MIN,
                                      1e-30f,
                                      1e-20f,
                                      std::nextafter(0x1p-63f, 0.0f),
                                      0x1p-63f,
                                      1e-19f,
                                      1e-10f,
                                      1e-5f,
                                      0.5f,
                                      1.0f,
                                      3.0f,
                                      1e5f,
                                      1e10f,
                                      1e18f,
                                      std::nextafter(0x1p64f, 0.0f),
                                      0x1p64f,
                                      1e20f,
                                      1e30f,
                                      1e38f,
                                      FLT_MAX,
                                      kInf,
                                      kNaN};
  constexpr std::size_t n = sizeof kMagnitudes / sizeof kMagnitudes[0];
  const float m = kMagnitudes[std::uniform_int_distribution<std::size_t>(0, n - 1)(rng)];
  return rng() % 2 ? -m : m;
}

// Usually an ordinary value at the scene's scale, sometimes a special one.
float field(std::mt19937& rng, float scale, float lo, float hi) {
  if (rng() % 6 == 0) return special(rng);
  return test::uniform(rng, lo, hi) * scale;
}

// The scale of a scene: tiny scenes are where squares underflow, huge ones where they overflow.
float random_scale(std::mt19937& rng) {
  const float scales[] = {1e-30f, 1e-20f, 0x1p-63f, 1e-10f, 1.0f, 1e10f, 1e19f, 1e30f};
  return scales[rng() % (sizeof scales / sizeof scales[0])];
}

test::LooseSpheres random_spheres(std::mt19937& rng, std::size_t n, float scale) {
  test::LooseSpheres s;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 c{field(rng, scale, -10, 10), field(rng, scale, -10, 10),
                 field(rng, scale, -10, 10)};
    s.add(c, field(rng, scale, 0.2f, 3.0f));
  }
  return s;
}

Ray random_ray(std::mt19937& rng, float scale) {
  Ray r{{field(rng, scale, -12, 12), field(rng, scale, -12, 12), field(rng, scale, -12, 12)},
        {field(rng, 1.0f, -1, 1), field(rng, 1.0f, -1, 1), field(rng, 1.0f, -1, 1)}};
  if (rng() % 4 == 0) r.tmin = special(rng);
  if (rng() % 4 == 0) r.tmax = special(rng);
  return r;
}

// The contract's valid sphere: finite fields and a radius whose square is a normal finite float.
bool contract_valid(const SphereView& v, std::uint32_t id) {
  const float r = v.radius[id];
  return std::isfinite(v.cx[id]) && std::isfinite(v.cy[id]) && std::isfinite(v.cz[id]) &&
         r >= 0x1p-63f && r < 0x1p64f;
}

// The same hit, bit for bit, except for the sign of a zero t: when two spheres tie at t = 0,
// one at +0 and one at -0, the SIMD reduction keeps the lower id but may report the other's
// zero (left open: docs/robustness.md, "Not done").
bool same(const Hit& a, const Hit& b) {
  if (a.id == b.id && a.t == 0.0f && b.t == 0.0f) return true;
  return a.id == b.id && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t);
}

// Counts failures per check and keeps the first few of each.
struct Failures {
  std::size_t count = 0;
  std::map<std::string, std::size_t> per_check;
  std::string first;
  void add(const std::string& check, const std::string& what) {
    ++count;
    if (per_check[check]++ < 3) first += check + ": " + what + "\n";
  }
  std::string summary() const {
    std::string text;
    for (const auto& [check, n] : per_check)
      text += "  " + check + ": " + std::to_string(n) + "\n";
    return text + "the first of each:\n" + first;
  }
};

// Every query of the spheres, brute force on instruction set k and through a tree laid out for
// it, against the scalar reference and against each other.
void check_scene(const EntryTable& k, const test::LooseSpheres& spheres,
                 const std::vector<Ray>& rays, Failures& failures) {
  const SphereView view = spheres.view();
  const SphereBVH bvh(view, k.isa);
  std::vector<Hit> tree_stream(rays.size()), brute_stream(rays.size());
  std::vector<char> tree_blocked(rays.size());
  {
    auto b = std::make_unique<bool[]>(rays.size());
    occluded(bvh, rays, std::span<bool>(b.get(), rays.size()));
    for (std::size_t i = 0; i < rays.size(); ++i)
      tree_blocked[i] = b[i];
  }
  intersect(bvh, rays, tree_stream);
  k.intersect_stream(view, rays.data(), brute_stream.data(), rays.size());
  const std::string where =
      std::string(isa_name(k.isa)) + ", " + std::to_string(view.count) + " spheres: ";
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Ray& ray = rays[i];
    const Hit ref = scalar::intersect(view, ray);
    const Hit brute = k.intersect(view, ray);
    const Hit tree = intersect(bvh, ray);
    const std::string tag = where + describe(ray) + " ref id " + std::to_string(ref.id) + " t " +
                            hex(ref.t) + ", brute id " + std::to_string(brute.id) + " t " +
                            hex(brute.t) + ", tree id " + std::to_string(tree.id) + " t " +
                            hex(tree.t);
    if (!same(brute, ref)) failures.add("brute != scalar reference", tag);
    auto tree_check = [&](bool ok, const char* check) {
      if (!ok) failures.add(check, tag);
    };
    tree_check(same(tree, brute), "tree != brute force");
    if (!same(brute_stream[i], brute)) failures.add("brute stream != brute", tag);
    if (!same(tree_stream[i], tree)) failures.add("tree stream != tree", tag);
    if (ref.found() && !contract_valid(view, ref.id)) failures.add("invalid sphere hit", tag);
    const bool found = ref.found();
    if (k.occluded(view, ray) != found) failures.add("brute occluded != found", tag);
    tree_check(occluded(bvh, ray) == found, "tree occluded != found");
    if (scalar::occluded(view, ray) != found) failures.add("scalar occluded != found", tag);
    tree_check((tree_blocked[i] != 0) == found, "tree occluded stream != found");
    Hit first[1];
    const std::size_t all = k.intersect_all(view, ray, first, nullptr, 1);
    if ((all > 0) != found) failures.add("count_hits > 0 != found", tag);
    if (all > 0 && !same(first[0], ref)) failures.add("first crossing != closest hit", tag);
    if (scalar::intersect_all(view, ray, {}, {}) != all)
      failures.add("scalar count != brute count", tag);
    tree_check(count_hits(bvh, ray) == all, "tree count != brute count");
    if (found) {
      const Surface s = surface(view, ray, ref);
      if (!(std::fabs(length(s.normal) - 1.0f) < 1e-5f))
        failures.add("surface normal not unit", tag);
    }
    // The point queries at the ray's origin: nearest, inside and overlapping agree with each
    // other, brute force with the tree, and find only valid spheres.
    const Vec3 p = ray.origin;
    const Nearest near_ref = scalar::nearest(view, p);
    const Hit near_brute = k.nearest(view, p, kInf);
    const Nearest near_tree = nearest(bvh, p);
    const std::string ptag =
        where + "point (" + hex(p.x) + ", " + hex(p.y) + ", " + hex(p.z) + ") ref id " +
        std::to_string(near_ref.id) + " d " + hex(near_ref.distance) + ", brute id " +
        std::to_string(near_brute.id) + ", tree id " + std::to_string(near_tree.id);
    if (near_brute.id != near_ref.id) failures.add("nearest brute != scalar", ptag);
    if (near_tree.id != near_ref.id) failures.add("nearest tree != brute", ptag);
    if (near_ref.found() && !contract_valid(view, near_ref.id))
      failures.add("nearest found an invalid sphere", ptag);
    const bool in = near_ref.found() && near_ref.distance < 0.0f;
    if (inside(bvh, p) != in) failures.add("tree inside != nearest < 0", ptag);
    if (inside(view, p) != in) failures.add("inside != nearest < 0", ptag);
    std::uint32_t ids[1];
    if ((overlapping(bvh, p, 0.0f, ids) > 0) != in)
      failures.add("tree overlapping(p, 0) != inside", ptag);
    if ((scalar::overlapping(view, p, 0.0f, ids) > 0) != in)
      failures.add("overlapping(p, 0) != inside", ptag);
  }
}

// Random scenes and rays with special values in every field, on every instruction set.
TEST(Specials, EveryQueryAgreesOnEveryInstructionSet) {
  std::mt19937 rng(30);
  const std::size_t sizes[] = {1, 3, 17, 200};
  const std::size_t rays_per_scene = test::scaled(1000);
  for (const EntryTable* k : test::runnable_kernels()) {
    Failures failures;
    std::size_t traced = 0;
    for (int scene = 0; scene < 100; ++scene) {
      const float scale = random_scale(rng);
      const auto spheres = random_spheres(rng, sizes[scene % 4], scale);
      std::vector<Ray> rays;
      for (std::size_t i = 0; i < rays_per_scene; ++i)
        rays.push_back(random_ray(rng, scale));
      // Coherent rays from one origin, which the tree's stream sends through in packets.
      Ray base = random_ray(rng, scale);
      for (std::size_t i = 0; i < rays_per_scene; ++i) {
        Ray r = base;
        r.dir =
            base.dir + Vec3{test::uniform(rng, -1e-3f, 1e-3f), test::uniform(rng, -1e-3f, 1e-3f),
                            test::uniform(rng, -1e-3f, 1e-3f)} *
                           std::fabs(base.dir.x);
        rays.push_back(r);
      }
      check_scene(*k, spheres, rays, failures);
      traced += rays.size();
    }
    EXPECT_EQ(failures.count, 0u) << test::name_of(k) << ", " << traced << " rays:\n"
                                  << failures.summary();
  }
}

// The roots' q = b' + sign(b') |d| sqrt(disc) at the ends of float's range, where |d|^2 r^2
// (the product sqrt(a disc) formed) overflows or underflows although every other intermediate
// and the answer are ordinary floats. Each case's t is the exact root, worked out by hand.
struct FarEndCase {
  const char* name;
  Vec3 center;
  float radius;
  Ray ray;
  float t;
};

TEST(Specials, RootsAtTheEndsOfTheRangeAreExact) {
  const FarEndCase cases[] = {
      // |d|^2 r^2 = 1e56: sqrt(a disc) was inf, and the near root c / q a false hit at t = 0.
      {"long direction, large sphere",
       {0, 0, 0},
       1e10f,
       Ray{{0, 0, -3e10f}, {0, 0, 1e18f}, -1.0f},
       2e-8f},
      // |d|^2 r^2 = 1e-60: sqrt(a disc) was 0, and a ray from the centre missed.
      {"short direction, tiny sphere", {0, 0, 0}, 1e-15f, Ray{{0, 0, 0}, {1e-15f, 0, 0}}, 1.0f},
  };
  for (const FarEndCase& c : cases) {
    // The sphere first, then spheres the ray never meets: batches of several lanes, not the
    // scalar loop that a single sphere takes.
    test::LooseSpheres spheres;
    spheres.add(c.center, c.radius);
    for (int i = 1; i <= 8; ++i)
      spheres.add(c.center + Vec3{0, 4.0f * i * c.radius, 0}, c.radius);
    const SphereView view = spheres.view();
    const auto check = [&](const Hit& hit, const std::string& who) {
      EXPECT_EQ(hit.id, 0u) << c.name << ", " << who;
      EXPECT_NEAR(hit.t, c.t, 1e-5f * c.t) << c.name << ", " << who;
    };
    check(scalar::intersect(view, c.ray), "scalar reference");
    for (const EntryTable* k : test::runnable_kernels()) {
      check(k->intersect(view, c.ray), std::string("brute force, ") + test::name_of(k));
      check(intersect(SphereBVH(view, k->isa), c.ray), std::string("tree, ") + test::name_of(k));
    }
  }
}

}  // namespace
}  // namespace sphray
