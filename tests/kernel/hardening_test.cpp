// Regression tests for defects the fuzzers found (docs/robustness.md, "Defects found"). Each
// test reproduces the input that failed, reduced by hand to what matters.
#include <cmath>
#include <limits>

#include "test_support.hpp"

namespace sphray {
namespace {

// A few spheres, so that every instruction set's tree takes the scalar traversal (trees of
// fewer than 8 spheres do), and a scalar tree over many.
std::vector<SphereSoA> scenes() {
  std::mt19937 rng(3);
  SphereSoA few, many;
  test::fill_random(few, 3, rng);
  test::fill_random(many, 200, rng);
  return {few, many};
}

// Fuzzer: a ray with a NaN origin read far outside the node array of the scalar BVH traversal
// (its NaN slabs bounded nothing, so it entered the empty child slots and followed their
// references). The contract: an invalid ray misses everything, with t == tmax.
TEST(Hardening, InvalidRaysMissInTheScalarBvhTraversal) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = INFINITY;
  const Ray invalid[] = {
      {{nan, 0, 0}, {0, 0, -1}},
      {{0, 0, 0}, {0, nan, -1}},
      {{inf, -12, nan}, {-12, nan, -2}},
      {{0, 0, 0}, {0, inf, -12}},
      {{0, 0, 0}, {0, 0, 0}},
      {{0, 0, 0}, {0, 0, -1}, 2.0f, 1.0f},
      {{0, 0, 0}, {0, 0, -1}, nan, 5.0f},
  };
  for (const SphereSoA& spheres : scenes())
    for (Isa isa : supported_isas()) {
      if (isa != Isa::scalar && spheres.size() >= 8) continue;
      const SphereBVH bvh(spheres.view(), isa);
      for (const Ray& ray : invalid) {
        const Hit hit = intersect(bvh, ray);
        EXPECT_FALSE(hit.found()) << isa_name(isa) << ", " << spheres.size() << " spheres";
        EXPECT_TRUE(std::isnan(ray.tmax) ? std::isnan(hit.t) : hit.t == ray.tmax);
        EXPECT_FALSE(occluded(bvh, ray)) << isa_name(isa);
      }
    }
}

// Fuzzer: with a negative tmin the ray meets boxes behind its origin, where Ize's conservative
// slab test (tnear <= tfar * (1 + 2 gamma(3))) is not conservative: it shrank a negative tfar
// and skipped the box of sphere 4, which brute force hits at t = -1. A SphereBVH must answer
// exactly what brute force answers on the same instruction set.
TEST(Hardening, BoxesBehindTheOriginAreNotSkipped) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float tiny = 0x1p-19f;
  test::LooseSpheres spheres(0);
  spheres.add({0, 1, 0}, 0);
  spheres.add({0, 0, -3}, nan);
  spheres.add({0, 0x1.3f6p+3f, -0x1.1ep-134f}, 0x1.7fcp+2f);
  spheres.add({nan, 0, 0}, 0);
  spheres.add({0, 0, -tiny}, tiny);
  spheres.add({-tiny, -tiny, -tiny}, tiny);
  spheres.add({-tiny, -tiny, -tiny}, tiny);
  spheres.add({-0x1p-28f, 0, -2}, 0);
  const float c = -0x1.999cp+6f;  // -102.40234375
  const Ray ray{{c, c, c}, {c, c, c}, c};
  for (Isa isa : supported_isas()) {
    const EntryTable& k = *find_entries(isa);
    const SphereBVH bvh(spheres.view(), isa);
    const Hit brute = k.intersect(spheres.view(), ray), tree = intersect(bvh, ray);
    EXPECT_TRUE(brute.found()) << isa_name(isa);
    EXPECT_EQ(tree.id, brute.id) << isa_name(isa);
    EXPECT_EQ(tree.t, brute.t) << isa_name(isa);
    EXPECT_EQ(occluded(bvh, ray), brute.found()) << isa_name(isa);
  }
}

// Kernel fuzzer: for a sphere of radius 1e-22 the offset from the centre to the hit point has
// squares in float's denormals, and surface() normalised it to a length of 0.985. Such a radius
// is invalid since issue 30 (its square underflows); the smallest valid one, 2^-63, still has
// offsets whose components square into the denormals.
TEST(Hardening, SurfaceNormalOfATinySphereIsUnitLength) {
  test::LooseSpheres spheres(0);
  spheres.add({0x1.b848p-6f, 0x1.26a6ap-130f, 0x1.35p-73f}, 0x1p-63f);
  const Ray ray{{0, 0, 0}, {0x1.368p+3f, 0, 0}};
  for (Isa isa : supported_isas()) {
    const Hit hit = find_entries(isa)->intersect(spheres.view(), ray);
    ASSERT_TRUE(hit.found()) << isa_name(isa);
    const Surface s = surface(spheres.view(), ray, hit);
    EXPECT_NEAR(length(s.normal), 1.0f, 1e-6f) << isa_name(isa);
  }
}

}  // namespace
}  // namespace sphray
