// docs/kernel.md, "One answer on every instruction set": every kernel, the scalar reference, the
// dispatched queries (which pick a kernel by view size) and the tree return the same t and id,
// bit for bit, for every ray, including rays that start on a sphere where float decides whether
// the near root lies above tmin.
#include <cmath>
#include <cstring>

#include "test_support.hpp"

namespace sphray {
namespace {

bool same_bits(const Hit& a, const Hit& b) {
  return a.id == b.id && std::memcmp(&a.t, &b.t, sizeof(float)) == 0;
}

// n random spheres, one in 16 replaced by an invalid one (radius 0 or negative, a NaN or
// infinite field).
SphereSoA random_scene(std::size_t n, std::mt19937& rng) {
  SphereSoA s;
  test::fill_random(s, n, rng);
  SphereSoA poisoned;
  const SphereView v = s.view();
  const float bad[] = {0.0f, -1.0f, NAN, INFINITY};
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 c{v.cx[i], v.cy[i], v.cz[i]};
    float r = v.radius[i];
    if (rng() % 16 == 0) (rng() % 2 == 0 ? r : c.y) = bad[rng() % 4];
    poisoned.add(c, r);
  }
  return poisoned;
}

// Half the rays random, half started on a random sphere's surface with tmin = 0, where the near
// root is a rounding of 0.
std::vector<Ray> mixed_rays(SphereView v, std::size_t n, std::mt19937& rng) {
  std::vector<Ray> rays = test::random_rays(n, rng);
  for (std::size_t i = 0; v.count > 0 && i < n; i += 2) {
    const std::size_t j = rng() % v.count;
    const Vec3 c{v.cx[j], v.cy[j], v.cz[j]};
    const Vec3 n_out = normalize(test::random_in_box(rng, 1.0f) + Vec3{1e-3f, 0, 0});
    rays[i].origin = c + v.radius[j] * n_out;
  }
  return rays;
}

TEST(OneAnswer, EveryKernelTheReferenceTheDispatcherAndTheTreeAgreeBitForBit) {
  std::mt19937 rng(20261123);
  const auto kernels = test::runnable_kernels();
  std::size_t compared = 0, mismatches = 0, traced = 0, hits = 0;
  std::vector<std::size_t> sizes;
  for (std::size_t n = 0; n <= 40; ++n)
    sizes.push_back(n);
  sizes.insert(sizes.end(), {100, 1000});
  for (const std::size_t n : sizes) {
    const SphereSoA scene = random_scene(n, rng);
    const SphereView v = scene.view();
    const std::vector<Ray> rays = mixed_rays(v, test::scaled(n >= 100 ? 4000 : 1000), rng);
    std::vector<SphereBVH> trees;
    for (const EntryTable* k : kernels)
      trees.emplace_back(v, k->isa);
    for (const Ray& ray : rays) {
      const Hit want = scalar::intersect(v, ray);
      const bool want_blocked = scalar::occluded(v, ray);
      ++traced;
      hits += want.found();
      auto check = [&](const Hit& got, bool blocked, const char* what, const EntryTable* k) {
        ++compared;
        const bool ok = same_bits(got, want) && blocked == want_blocked;
        mismatches += !ok;
        EXPECT_TRUE(ok) << what << " " << (k ? test::name_of(k) : "") << ", " << n
                        << " spheres: id " << got.id << " t " << got.t << ", reference id "
                        << want.id << " t " << want.t;
      };
      check(intersect(v, ray), occluded(v, ray), "dispatched", nullptr);
      for (std::size_t k = 0; k < kernels.size(); ++k) {
        check(kernels[k]->intersect(v, ray), kernels[k]->occluded(v, ray), "kernel", kernels[k]);
        check(intersect(trees[k], ray), occluded(trees[k], ray), "tree", kernels[k]);
      }
      if (mismatches > 10) FAIL() << "stopping after " << mismatches << " mismatches";
    }
  }
  std::cout << "[ compared ] " << compared << " answers bit for bit, " << mismatches
            << " unlike the scalar reference\n";
  EXPECT_GT(hits, traced / 4) << "too few hits for the comparison to bite";
}

}  // namespace
}  // namespace sphray
