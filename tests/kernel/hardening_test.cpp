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

}  // namespace
}  // namespace sphray
