// Queries on one const scene from many threads give what one thread gives.
#include <thread>

#include "test_support.hpp"

namespace sphray {
namespace {

TEST(Concurrency, ConstQueriesFromManyThreadsAgree) {
  std::mt19937 rng(5);
  SphereSoA spheres;
  test::fill_random(spheres, 500, rng);
  const SphereSoA& scene = spheres;
  const auto rays = test::random_rays(4000, rng);
  std::vector<Hit> expected(rays.size());
  intersect(scene.view(), rays, expected);

  constexpr int kThreads = 8;
  std::vector<std::vector<Hit>> got(kThreads, std::vector<Hit>(rays.size()));
  std::vector<std::vector<char>> occ(kThreads, std::vector<char>(rays.size()));
  {
    std::vector<std::jthread> threads;
    for (int t = 0; t < kThreads; ++t)
      threads.emplace_back([&, t] {
        for (std::size_t i = 0; i < rays.size(); ++i) {
          got[t][i] = intersect(scene.view(), rays[i]);
          occ[t][i] = occluded(scene.view(), rays[i]);
        }
      });
  }
  for (int t = 0; t < kThreads; ++t)
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(got[t][i].id, expected[i].id);
      ASSERT_EQ(got[t][i].t, expected[i].t);
      ASSERT_EQ(occ[t][i] != 0, expected[i].found());
    }
}

TEST(Concurrency, ConstBvhQueriesFromManyThreadsAgree) {
  std::mt19937 rng(6);
  SphereSoA spheres;
  test::fill_random(spheres, 3000, rng);
  const SphereBVH bvh(spheres.view());
  const auto rays = test::random_rays(4000, rng);
  std::vector<Hit> expected(rays.size());
  intersect(bvh, rays, expected);

  constexpr int kThreads = 8;
  std::vector<std::vector<Hit>> got(kThreads, std::vector<Hit>(rays.size()));
  {
    std::vector<std::jthread> threads;
    for (int t = 0; t < kThreads; ++t)
      threads.emplace_back([&, t] {
        for (std::size_t i = 0; i < rays.size(); ++i)
          got[t][i] = intersect(bvh, rays[i]);
      });
  }
  for (int t = 0; t < kThreads; ++t)
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(got[t][i].id, expected[i].id);
      ASSERT_EQ(got[t][i].t, expected[i].t);
    }
}

}  // namespace
}  // namespace sphray
