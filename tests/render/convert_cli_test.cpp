// `sphray convert IN OUT`: every format round-trips the same spheres bit for bit, a preset
// converts to its own spheres and colours, and a refusal (bad input, unknown extension) exits
// with status 2, one line, and leaves an existing OUT as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <fstream>
#include <string>

#include "command_run.hpp"
#include "sphray/particles/particles.hpp"
#include "sphray/render/scene.hpp"
#include "test_files.hpp"

namespace {

using sphray::test::read_bytes;
using sphray::test::run_sphray;
using sphray::test::write_text;

class ConvertCli : public sphray::test::ScratchDirTest {
 protected:
  ConvertCli() : ScratchDirTest("sphray-convert-cli-") {}
};

void write_sphp_file(const std::string& file, const sphray::SphereSoA& spheres) {
  std::ofstream out(file, std::ios::binary);
  sphray::particles::write_sphp(
      [&](const void* data, std::size_t size) {
        out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
      },
      spheres.view());
}

// Floats whose shortest decimal text is long or unusual: 0.1f, a subnormal-adjacent value, the
// largest allowed magnitude, -0, and values that need nine significant digits.
sphray::SphereSoA awkward_spheres() {
  sphray::SphereSoA spheres;
  spheres.add({0.1f, -0.0f, 1e17f}, 1e-30f);
  spheres.add({1.17549435e-38f, -3.40282e16f, 16777217.0f}, 0.3f);
  spheres.add({std::bit_cast<float>(0x3f8ccccdu), std::bit_cast<float>(0xbe99999au), 7.0f},
              std::bit_cast<float>(0x3eaaaaabu));
  return spheres;
}

void expect_same_bits(sphray::SphereView a, sphray::SphereView b) {
  ASSERT_EQ(a.count, b.count);
  for (std::size_t i = 0; i < a.count; ++i) {
    for (auto [x, y] : {std::pair{a.cx[i], b.cx[i]}, std::pair{a.cy[i], b.cy[i]},
                        std::pair{a.cz[i], b.cz[i]}, std::pair{a.radius[i], b.radius[i]}}) {
      EXPECT_EQ(std::bit_cast<std::uint32_t>(x), std::bit_cast<std::uint32_t>(y)) << "sphere " << i;
    }
  }
}

TEST_F(ConvertCli, SphpToXyzToCsvToPlyToSphpIsTheSameFileBitForBit) {
  write_sphp_file(path("a.sphp"), awkward_spheres());
  const char* steps[][2] = {
      {"a.sphp", "b.xyz"}, {"b.xyz", "c.csv"}, {"c.csv", "d.ply"}, {"d.ply", "e.sphp"}};
  for (const auto& step : steps) {
    const auto r = run_sphray(std::string("convert -q ") + path(step[0]) + " " + path(step[1]));
    ASSERT_EQ(r.status, 0) << step[0] << " -> " << step[1] << ": " << r.out;
    EXPECT_EQ(r.out, "");
  }
  EXPECT_EQ(read_bytes(path("e.sphp")), read_bytes(path("a.sphp")));
  EXPECT_TRUE(read_bytes(path("d.ply")).starts_with("ply\nformat binary_little_endian 1.0\n"));
  EXPECT_TRUE(read_bytes(path("b.xyz")).starts_with("x y z radius\n0.1 -0 1e+17 1e-30\n"))
      << read_bytes(path("b.xyz"));
  EXPECT_TRUE(read_bytes(path("c.csv")).starts_with("x,y,z,radius\n0.1,-0,1e+17,1e-30\n"));
}

TEST_F(ConvertCli, APresetConvertsToItsOwnSpheresAndColours) {
  const sphray::render::Scene scene = sphray::render::load_scene_or_preset("random:50");
  const auto r = run_sphray("convert random:50 " + path("r.sphp"));
  ASSERT_EQ(r.status, 0) << r.out;
  const std::string bytes = std::to_string(32 + 16 * 50);
  EXPECT_TRUE(
      r.out.starts_with("wrote " + path("r.sphp") + ": 50 particles, " + bytes + " bytes, "))
      << r.out;
  expect_same_bits(sphray::particles::read_sphp(path("r.sphp")).view(), scene.spheres.view());

  ASSERT_EQ(run_sphray("convert -q random:50 " + path("r.csv")).status, 0);
  const sphray::particles::Points points = sphray::particles::read_points(path("r.csv"));
  expect_same_bits(points.spheres.view(), scene.spheres.view());
  ASSERT_EQ(points.colors.size(), scene.colors.size());
  for (std::size_t i = 0; i < scene.colors.size(); ++i) {
    EXPECT_EQ(points.colors[i].x, scene.colors[i].x);
    EXPECT_EQ(points.colors[i].y, scene.colors[i].y);
    EXPECT_EQ(points.colors[i].z, scene.colors[i].z);
  }
}

TEST_F(ConvertCli, AFileWithoutColoursGetsNoneAndARadiusCanBeGiven) {
  write_text(path("p.xyz"), "1 2 3\n4 5 6\n");
  ASSERT_EQ(run_sphray("convert -q --radius 0.25 " + path("p.xyz") + " " + path("p.csv")).status,
            0);
  EXPECT_EQ(read_bytes(path("p.csv")), "x,y,z,radius\n1,2,3,0.25\n4,5,6,0.25\n");
}

TEST_F(ConvertCli, RefusalsLeaveTheOutputUntouched) {
  const std::string original = "an earlier conversion, which must survive";
  struct Case {
    std::string args;
    std::string message;
  };
  write_text(path("bad.xyz"), "1 2 3 1\n1 2 x 1\n");
  write_text(path("good.xyz"), "1 2 3 1\n");
  const Case cases[] = {
      {path("bad.xyz") + " " + path("out.sphp"),
       path("bad.xyz") + ":2: expected column 3 (z) to be a number, got \"x\""},
      {path("none.xyz") + " " + path("out.sphp"),
       path("none.xyz") + ": cannot read the particle file (No such file or directory)"},
      {path("good.xyz") + " " + path("out.txt"),
       path("out.txt") + ": expected an output particle file ending in .sphp, .xyz, .csv or .ply"},
      {"no-such-preset " + path("out.sphp"), ""},
  };
  for (const Case& c : cases) {
    for (const char* out : {"out.sphp", "out.txt", "out.ply"})
      write_text(path(out), original);
    const auto r = run_sphray("convert " + c.args);
    EXPECT_EQ(r.status, 2) << c.args << ": " << r.out;
    if (!c.message.empty()) {
      EXPECT_EQ(r.out, "sphray: " + c.message + "\n");
    }
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    for (const char* out : {"out.sphp", "out.txt", "out.ply"})
      EXPECT_EQ(read_bytes(path(out)), original) << c.args;
  }
  EXPECT_EQ(run_sphray("convert " + path("good.xyz")).status, 2);  // OUT missing
}

}  // namespace
