// The C loader (sphray_particles.h, libsphray_particles.so) as a C program sees it: a file's
// particles give the same hits through the C API as the same spheres given in memory, a bad
// file is refused with a status and a message naming the file and line, and NULL arguments
// give an error, never a crash.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <sphray/sphray.h>
#include <sphray/sphray_particles.h>

namespace {

class CParticles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("sphray-c-particles-" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "-" +
            std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string file = (dir_ / name).string();
    std::ofstream(file, std::ios::binary) << bytes;
    return file;
  }
  std::filesystem::path dir_;
};

// The hits of a fan of rays from in front of the spheres, through a scene of those arrays.
std::vector<sphray_hit> hits_of(const float* cx, const float* cy, const float* cz, const float* r,
                                size_t count) {
  sphray_scene* scene = nullptr;
  EXPECT_EQ(sphray_scene_create(cx, cy, cz, r, count, 0, nullptr, &scene), SPHRAY_OK)
      << sphray_last_error();
  std::vector<sphray_ray> rays;
  for (int i = 0; i < 64; ++i) {
    for (int j = 0; j < 16; ++j) {
      rays.push_back({-3.0f + 0.1f * static_cast<float>(i), -0.8f + 0.1f * static_cast<float>(j),
                      5.0f, 0.0f, 0.0f, -1.0f, 0.0f, INFINITY});
    }
  }
  std::vector<sphray_hit> hits(rays.size());
  EXPECT_EQ(sphray_intersect(scene, rays.data(), rays.size(), hits.data(), nullptr), SPHRAY_OK);
  sphray_scene_release(scene);
  return hits;
}

void expect_same_hits(const std::vector<sphray_hit>& a, const std::vector<sphray_hit>& b) {
  ASSERT_EQ(a.size(), b.size());
  int hit = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id) << "ray " << i;
    EXPECT_EQ(std::memcmp(&a[i].t, &b[i].t, sizeof(float)), 0) << "ray " << i;
    hit += a[i].id != SPHRAY_NO_HIT;
  }
  EXPECT_GT(hit, 10);  // the rays do meet the spheres
}

const float kCx[] = {-1.5f, 0.1f, 1.7f}, kCy[] = {0.0f, 0.25f, -0.3f}, kCz[] = {0, -0.5f, 0.2f},
            kR[] = {0.5f, 0.75f, 0.6f};

TEST_F(CParticles, ATextFileGivesTheSameHitsAsTheSameSpheresInMemory) {
  const std::string file = write("cloud.csv",
                                 "x,y,z,radius,red,green,blue\n"
                                 "-1.5,0,0,0.5,1,0,0\n0.1,0.25,-0.5,0.75,0,1,0\n"
                                 "1.7,-0.3,0.2,0.6,0,0,0.5\n");
  sphray_particles* p = nullptr;
  ASSERT_EQ(sphray_particles_load(file.c_str(), 0.0f, &p), SPHRAY_OK)
      << sphray_particles_last_error();
  size_t count = 0;
  ASSERT_EQ(sphray_particles_count(p, &count), SPHRAY_OK);
  EXPECT_EQ(count, 3u);
  sphray_particle_arrays a;
  ASSERT_EQ(sphray_particles_arrays(p, &a), SPHRAY_OK);
  ASSERT_EQ(a.count, 3u);
  ASSERT_NE(a.red, nullptr);
  EXPECT_EQ(a.red[0], 1.0f);
  EXPECT_EQ(a.green[1], 1.0f);
  EXPECT_EQ(a.blue[2], 0.5f);
  expect_same_hits(hits_of(a.cx, a.cy, a.cz, a.r, a.count), hits_of(kCx, kCy, kCz, kR, 3));
  EXPECT_EQ(sphray_particles_release(p), SPHRAY_OK);
}

TEST_F(CParticles, ASphpFileAndAGivenRadius) {
  std::string bytes("SPHRAYP\0\1\0\0\0\0\0\0\0\3\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0", 32);
  for (int i = 0; i < 3; ++i) {
    for (float v : {kCx[i], kCy[i], kCz[i], kR[i]})
      bytes.append(reinterpret_cast<const char*>(&v), 4);  // little-endian hosts only
  }
  sphray_particles* p = nullptr;
  ASSERT_EQ(sphray_particles_load(write("cloud.sphp", bytes).c_str(), -1.0f, &p), SPHRAY_OK)
      << sphray_particles_last_error();
  sphray_particle_arrays a;
  ASSERT_EQ(sphray_particles_arrays(p, &a), SPHRAY_OK);
  EXPECT_EQ(a.red, nullptr);  // a .sphp file has no colours
  expect_same_hits(hits_of(a.cx, a.cy, a.cz, a.r, a.count), hits_of(kCx, kCy, kCz, kR, 3));
  sphray_particles_release(p);

  const std::string xyz = write("no_radius.xyz", "-1.5 0 0\n0.1 0.25 -0.5\n");
  ASSERT_EQ(sphray_particles_load(xyz.c_str(), 0.5f, &p), SPHRAY_OK);
  ASSERT_EQ(sphray_particles_arrays(p, &a), SPHRAY_OK);
  EXPECT_EQ(a.count, 2u);
  EXPECT_EQ(a.r[1], 0.5f);
  sphray_particles_release(p);
}

TEST_F(CParticles, BadFilesAreRefusedWithTheFileAndLine) {
  sphray_particles* untouched = reinterpret_cast<sphray_particles*>(&untouched);
  sphray_particles* p = untouched;
  const std::string bad = write("bad.xyz", "1 2 3 1\n1 2 x 1\n");
  EXPECT_EQ(sphray_particles_load(bad.c_str(), 0.0f, &p), SPHRAY_ERROR_PARTICLE_FILE);
  EXPECT_EQ(
      std::string(sphray_particles_last_error()),
      "sphray_particles_load: " + bad + ":2: expected column 3 (z) to be a number, got \"x\"");
  EXPECT_EQ(p, untouched);
  const std::string no_radius = write("no_radius.xyz", "1 2 3\n");
  EXPECT_EQ(sphray_particles_load(no_radius.c_str(), 0.0f, &p), SPHRAY_ERROR_PARTICLE_FILE);
  EXPECT_NE(std::string(sphray_particles_last_error()).find(no_radius + ":1: expected a radius"),
            std::string::npos)
      << sphray_particles_last_error();
  const std::string missing = (dir_ / "none.csv").string();
  EXPECT_EQ(sphray_particles_load(missing.c_str(), 1.0f, &p), SPHRAY_ERROR_PARTICLE_FILE);
  EXPECT_EQ(std::string(sphray_particles_last_error()),
            "sphray_particles_load: " + missing +
                ": cannot read the particle file (No such file or directory)");
  const std::string other = write("cloud.txt", "1 2 3 1\n");
  EXPECT_EQ(sphray_particles_load(other.c_str(), 1.0f, &p), SPHRAY_ERROR_PARTICLE_FILE);
  EXPECT_EQ(p, untouched);
}

TEST_F(CParticles, NullArgumentsGiveAnError) {
  const std::string file = write("one.xyz", "0 0 0 1\n");
  sphray_particles* p = nullptr;
  EXPECT_EQ(sphray_particles_load(nullptr, 1.0f, &p), SPHRAY_ERROR_NULL_POINTER);
  EXPECT_EQ(std::string(sphray_particles_last_error()), "sphray_particles_load: path is NULL");
  EXPECT_EQ(sphray_particles_load(file.c_str(), 1.0f, nullptr), SPHRAY_ERROR_NULL_POINTER);
  size_t count = 0;
  sphray_particle_arrays a;
  EXPECT_EQ(sphray_particles_count(nullptr, &count), SPHRAY_ERROR_NULL_POINTER);
  EXPECT_EQ(sphray_particles_arrays(nullptr, &a), SPHRAY_ERROR_NULL_POINTER);
  EXPECT_EQ(sphray_particles_release(nullptr), SPHRAY_ERROR_NULL_POINTER);
  ASSERT_EQ(sphray_particles_load(file.c_str(), 1.0f, &p), SPHRAY_OK);
  EXPECT_EQ(sphray_particles_count(p, nullptr), SPHRAY_ERROR_NULL_POINTER);
  EXPECT_EQ(sphray_particles_arrays(p, nullptr), SPHRAY_ERROR_NULL_POINTER);
  EXPECT_EQ(std::string(sphray_particles_last_error()), "sphray_particles_arrays: out is NULL");
  EXPECT_EQ(sphray_particles_release(p), SPHRAY_OK);
}

}  // namespace
