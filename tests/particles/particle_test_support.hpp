// What the particle readers' tests share: a scratch folder per test, spheres drawn from a fixed
// seed, and the check that two sets of spheres give the same hits, bit for bit.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "sphray/particles/particles.hpp"
#include "sphray/sphray.hpp"

namespace sphray::particles::test {

class ParticleFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("sphray-particles-" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "-" +
            std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path path(const std::string& name) const { return dir_ / name; }
  void write(const std::filesystem::path& file, const std::string& bytes) const {
    std::ofstream(file, std::ios::binary) << bytes;
  }
  std::filesystem::path dir_;
};

/// read() throws a ParticleError whose message is message.
template <typename Read>
void expect_refused(const Read& read, const std::string& message) {
  try {
    read();
    ADD_FAILURE() << "read without an error, where expected: " << message;
  } catch (const ParticleError& e) {
    EXPECT_EQ(e.what(), message);
  }
}

inline SphereSoA random_spheres(std::size_t n, unsigned seed = 11) {
  std::mt19937 rng(seed);
  const auto u = [&](float lo, float hi) {
    return lo + (hi - lo) * static_cast<float>(rng() >> 8) * 0x1p-24f;
  };
  SphereSoA spheres;
  for (std::size_t i = 0; i < n; ++i)
    spheres.add({u(-5, 5), u(-5, 5), u(-5, 5)}, u(0.05f, 0.4f));
  return spheres;
}

/// Rays from outside the spheres towards their centres, through the tree and by brute force:
/// every hit of read the same as of expected, id and t bit for bit.
inline void expect_same_hits(const SphereSoA& read, const SphereSoA& expected) {
  ASSERT_EQ(read.size(), expected.size());
  std::mt19937 rng(12);
  std::vector<Ray> rays(1000);
  for (Ray& ray : rays) {
    ray.origin = {0, 1, 20};
    ray.dir = expected.center(static_cast<std::uint32_t>(rng() % expected.size())) - ray.origin;
  }
  const SphereBVH tree_read(read.view()), tree_expected(expected.view());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    for (const auto& [got, want] :
         {std::pair{intersect(read.view(), rays[i]), intersect(expected.view(), rays[i])},
          std::pair{intersect(tree_read, rays[i]), intersect(tree_expected, rays[i])}}) {
      EXPECT_EQ(got.id, want.id) << "ray " << i;
      EXPECT_EQ(std::bit_cast<std::uint32_t>(got.t), std::bit_cast<std::uint32_t>(want.t));
    }
  }
}

}  // namespace sphray::particles::test
