// `sphray render -s FILE` with particle files (.xyz, .csv, .sphp): they render framed as
// random:N is, the same spheres give the same image from any format, and a bad file is refused
// with exit status 2, one line naming the file and line, and the output untouched.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <stb/stb_image.h>

#include "command_run.hpp"
#include "sphray/particles/particles.hpp"
#include "test_files.hpp"

namespace {

using sphray::test::read_bytes;
using sphray::test::run_sphray;
using sphray::test::write_text;

class ParticleCli : public sphray::test::ScratchDirTest {
 protected:
  ParticleCli() : ScratchDirTest("sphray-particle-cli-") {}
};

// Two spheres side by side, in every format.
const char kXyz[] = "# x y z r\n-1 0 0 0.5\n1 0 0 0.75\n";

TEST_F(ParticleCli, TheSameSpheresGiveTheSameImageFromEveryFormat) {
  write_text(path("a.xyz"), kXyz);
  write_text(path("a.csv"), "x,y,z,radius\n-1,0,0,0.5\n1,0,0,0.75\n");
  sphray::SphereSoA spheres;
  spheres.add({-1, 0, 0}, 0.5f);
  spheres.add({1, 0, 0}, 0.75f);
  std::ofstream out(path("a.sphp"), std::ios::binary);
  sphray::particles::write_sphp(
      [&](const void* data, std::size_t size) {
        out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
      },
      spheres.view());
  out.close();
  for (const char* mode : {"normals", "id"}) {
    std::string first;
    for (const char* file : {"a.xyz", "a.csv", "a.sphp"}) {
      const auto r = run_sphray(std::string("render -q -m ") + mode + " -W 64 -H 36 -s " +
                                path(file) + " -o " + path(std::string(file) + ".ppm"));
      ASSERT_EQ(r.status, 0) << file << ": " << r.out;
      const std::string image = read_bytes(path(std::string(file) + ".ppm"));
      if (first.empty()) first = image;
      EXPECT_EQ(image, first) << file << " in " << mode << " mode";
    }
  }
}

TEST_F(ParticleCli, AGivenRadiusAndTheFilesColoursAreUsed) {
  // One sphere, red in the file, framed so that it fills the middle of the image.
  write_text(path("red.csv"), "x,y,z,red,green,blue\n0,0,0,255,0,0\n");
  const auto r = run_sphray("render -m shaded --spp 1 -W 41 -H 23 --radius 2 -s " +
                            path("red.csv") + " -o " + path("red.png"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("41x23, 1 spp, shaded"), std::string::npos) << r.out;
  int w = 0, h = 0, channels = 0;
  stbi_uc* data = stbi_load(path("red.png").c_str(), &w, &h, &channels, 3);
  ASSERT_NE(data, nullptr);
  const stbi_uc* centre = data + 3 * (11 * 41 + 20);
  EXPECT_GT(centre[0], 100);
  EXPECT_EQ(centre[1], 0);
  EXPECT_EQ(centre[2], 0);
  stbi_image_free(data);
}

struct Refusal {
  std::string file;     // written into the test's folder
  std::string content;  // its bytes
  std::string args;     // after the scene
  std::string message;  // after "sphray: " and the file's path
};

TEST_F(ParticleCli, BadFilesAreRefusedAndTheOutputIsUntouched) {
  const Refusal refusals[] = {
      {"bad.xyz", "1 2 3 1\n1 2 x 1\n", "", ":2: expected column 3 (z) to be a number, got \"x\""},
      {"bad.csv", "x,y,z\n0,0,0\n", "",
       ":1: expected a radius column, or a radius given for the file (sphray render --radius R)"},
      {"bad.xyz", "1 2 3 -1\n", "--radius 1",
       ":1: expected column 4 (radius) to be positive, got \"-1\""},
      {"empty.xyz", "# nothing\n", "", ": expected particles, the file has none"},
      {"bad.sphp", "SPHRAYP", "", ": truncated: 7 bytes, less than the 32-byte header"},
      {"nan.sphp",
       std::string("SPHRAYP\0\1\0\0\0\0\0\0\0\1\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0", 32) +
           std::string("\0\0\0\0\0\0\0\0\0\0\xc0\x7f\0\0\x80\x3f", 16),
       "",
       ": particle 0 (byte offset 32): expected a centre of at most 1e17 in magnitude and a "
       "radius in (0, 1e17], got (0.000000, 0.000000, nan) r 1.000000"},
  };
  for (const Refusal& refusal : refusals) {
    const std::string output = path("out.png");
    const std::string original = "not really a PNG, but it must survive";
    write_text(output, original);
    write_text(path(refusal.file), refusal.content);
    const auto r =
        run_sphray("render -s " + path(refusal.file) + " " + refusal.args + " -o " + output);
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_EQ(r.out, "sphray: " + path(refusal.file) + refusal.message + "\n");
    EXPECT_EQ(read_bytes(output), original);
  }
  const auto missing = run_sphray("render -s " + path("none.xyz") + " -o " + path("out.png"));
  EXPECT_EQ(missing.status, 2);
  EXPECT_EQ(missing.out, "sphray: " + path("none.xyz") +
                             ": cannot read the particle file (No such file or directory)\n");
  EXPECT_EQ(run_sphray("render --radius -1 -s " + path("bad.xyz")).status, 2);
}

}  // namespace
