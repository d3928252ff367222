// `sphray render -s FILE` with particle files (.xyz, .csv, .sphp, .ply): they render framed as
// random:N is, the same spheres give the same image from any format, and a bad file is refused
// with exit status 2, one line naming the file and line, and the output untouched.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <stb/stb_image.h>

#include "command_run.hpp"
#include "sphray/particles/particles.hpp"
#include "test_files.hpp"
#include "test_pixels.hpp"

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
  const auto to_out = [&](const void* data, std::size_t size) {
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  };
  sphray::particles::write_sphp(to_out, spheres.view());
  out.close();
  out.open(path("a.ply"), std::ios::binary);
  sphray::particles::write_ply(to_out, spheres.view());
  out.close();
  write_text(path("b.ply"),
             "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
             "property float z\nproperty float radius\nend_header\n-1 0 0 0.5\n1 0 0 0.75\n");
  for (const char* mode : {"normals", "id"}) {
    std::string first;
    for (const char* file : {"a.xyz", "a.csv", "a.sphp", "a.ply", "b.ply"}) {
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

using sphray::test::load_pixels;
using sphray::test::Pixels;

// The camera the colour and material tests look through: on the +z axis at distance 10, looking
// at the origin, vfov 20, onto a square image of 101 pixels a side.
const char kCamera[] = " --lookfrom 0,0,10 --lookat 0,0,0 --vfov 20 -W 101 -H 101";
constexpr int kSide = 101;
const double kHalf = std::tan(10.0 * std::numbers::pi / 180.0);  // tan(vfov / 2)

// The pixel the point (x, y, z) projects to through kCamera (the book's pinhole, written out).
std::pair<int, int> pixel_of(double x, double y, double z) {
  const double scale = kSide / (2.0 * kHalf * (10.0 - z));
  return {static_cast<int>(kSide / 2.0 + x * scale), static_cast<int>(kSide / 2.0 - y * scale)};
}

// Two particles with colours that no mode's constant gives, left and right of the origin.
const char kTwoColours[] =
    "x y z radius red green blue\n-0.9 0 0 0.8 0.8 0.4 0.2\n"
    "0.9 0 0 0.8 0.1 0.5 0.9\n";

TEST_F(ParticleCli, FlatShadedAndPathModesShowEachParticlesColour) {
  write_text(path("two.xyz"), kTwoColours);
  const double colours[2][3] = {{0.8, 0.4, 0.2}, {0.1, 0.5, 0.9}};
  const std::pair<int, int> centres[2] = {pixel_of(-0.9, 0, 0.8), pixel_of(0.9, 0, 0.8)};
  for (const char* mode : {"flat", "shaded", "path"}) {
    const std::string out = path(std::string(mode) + ".png");
    const auto r = run_sphray(std::string("render -q --spp 16 -m ") + mode + kCamera + " -s " +
                              path("two.xyz") + " -o " + out);
    ASSERT_EQ(r.status, 0) << r.out;
    const Pixels image = load_pixels(out);
    ASSERT_EQ(image.width, kSide);
    for (int k = 0; k < 2; ++k) {
      const int* p = image.at(centres[k].first, centres[k].second);
      const double* c = colours[k];
      if (std::string(mode) == "flat") {  // the file's colour, unshaded: int(255.999 * c)
        for (int i = 0; i < 3; ++i)
          EXPECT_EQ(p[i], static_cast<int>(255.999 * c[i])) << "particle " << k;
      } else if (std::string(mode) == "shaded") {
        // colour * light, gamma 2: the squared bytes keep the colour's ratios. The light is
        // read off the brightest channel, whose byte rounds least in proportion.
        const int top = c[0] > c[2] ? 0 : 2;
        const double light = (p[top] + 0.5) / 255.999 / std::sqrt(c[top]);
        for (int i = 0; i < 3; ++i)
          EXPECT_NEAR(p[i], 255.999 * light * std::sqrt(c[i]), 1.5) << "particle " << k;
      } else {  // path: the albedo tints the sky, whose blue is never below its red
        EXPECT_EQ(p[0] > p[2], c[0] > c[2]) << "particle " << k;
      }
    }
  }
}

TEST_F(ParticleCli, AFileWithoutColoursRendersAsOneWithGreyColours) {
  write_text(path("plain.xyz"), "-0.9 0 0 0.8\n0.9 0 0 0.8\n0 0.9 -1 0.5\n");
  write_text(path("grey.xyz"),
             "-0.9 0 0 0.8 0.5 0.5 0.5\n0.9 0 0 0.8 0.5 0.5 0.5\n"
             "0 0.9 -1 0.5 0.5 0.5 0.5\n");
  for (const char* mode : {"shaded", "path"}) {
    for (const char* material : {"lambertian", "metal:0.3"}) {
      std::string images[2];
      for (int k = 0; k < 2; ++k) {
        const std::string out = path("out" + std::to_string(k) + ".ppm");
        const auto r =
            run_sphray(std::string("render -q --spp 4 -m ") + mode + " --material " + material +
                       kCamera + " -s " + path(k == 0 ? "plain.xyz" : "grey.xyz") + " -o " + out);
        ASSERT_EQ(r.status, 0) << r.out;
        images[k] = read_bytes(out);
      }
      EXPECT_EQ(images[0], images[1]) << mode << ", " << material;
    }
  }
}

// What a fuzzless mirror of albedo 1 shows through the centre of pixel (px, py) of kCamera: the
// sky gradient in the direction the ray leaves the unit sphere at the origin, gamma 2, as bytes.
std::vector<int> mirror_bytes(int px, int py) {
  const double scale = 2.0 * kHalf / kSide;
  double d[3] = {(px + 0.5 - kSide / 2.0) * scale, (kSide / 2.0 - py - 0.5) * scale, -1.0};
  const double o[3] = {0, 0, 10};
  const double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  const double b = o[2] * d[2];  // dot(o, d)
  const double t = (-b - std::sqrt(b * b - a * (100.0 - 1.0))) / a;
  const double n[3] = {t * d[0], t * d[1], o[2] + t * d[2]};  // unit: the sphere's radius is 1
  const double dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
  double r[3];
  for (int i = 0; i < 3; ++i)
    r[i] = d[i] - 2.0 * dn * n[i];
  const double up = 0.5 * (r[1] / std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) + 1.0);
  const double sky[3] = {1.0 - 0.5 * up, 1.0 - 0.3 * up, 1.0};
  return {static_cast<int>(255.999 * std::sqrt(sky[0])),
          static_cast<int>(255.999 * std::sqrt(sky[1])),
          static_cast<int>(255.999 * std::sqrt(sky[2]))};
}

TEST_F(ParticleCli, AMetalParticleMirrorsTheSkyWhereALambertianOneScattersIt) {
  write_text(path("white.xyz"), "0 0 0 1 1 1 1\n");
  Pixels images[2];
  const char* materials[2] = {"metal", "lambertian"};
  for (int k = 0; k < 2; ++k) {
    const std::string out = path(std::string(materials[k]) + ".png");
    const auto r = run_sphray(std::string("render -q -m path --spp 64 --material ") + materials[k] +
                              kCamera + " -s " + path("white.xyz") + " -o " + out);
    ASSERT_EQ(r.status, 0) << r.out;
    images[k] = load_pixels(out);
    ASSERT_EQ(images[k].width, kSide);
  }
  // Where the normal leans 45 degrees up, a mirror sends the view up into the blue zenith; 45
  // degrees down, into the white horizon. A Lambertian surface averages the sky over its normal's
  // hemisphere: paler than the mirror above, darker below.
  const double s = std::sqrt(0.5);
  for (const double lean : {s, -s}) {
    const auto [x, y] = pixel_of(0, lean, s);
    const std::vector<int> mirror = mirror_bytes(x, y);
    const int* metal = images[0].at(x, y);
    const int* lambertian = images[1].at(x, y);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(metal[i], mirror[i], 3) << "channel " << i << " at " << x << ", " << y;
    if (lean > 0) {
      EXPECT_GT(lambertian[0], mirror[0] + 10) << x << ", " << y;
    } else {
      EXPECT_LT(lambertian[0], mirror[0] - 10) << x << ", " << y;
    }
  }
}

TEST_F(ParticleCli, BadMaterialsAreRefusedAndOnlyParticleFilesTakeOne) {
  write_text(path("one.xyz"), "0 0 0 1\n");
  const std::pair<std::string, std::string> cases[] = {
      {"plastic", "--material: expected lambertian, metal[:FUZZ] or glass[:IOR], got plastic"},
      {"lambertian:1",
       "--material: expected lambertian, metal[:FUZZ] or glass[:IOR], got "
       "lambertian:1"},
      {"metal:x", "--material: expected lambertian, metal[:FUZZ] or glass[:IOR], got metal:x"},
      {"metal:2", "--material: expected \"fuzz\" in [0, 1], got 2"},
      {"metal:-0.5", "--material: expected \"fuzz\" in [0, 1], got -0.5"},
      {"glass:0", "--material: expected \"ior\" to be positive, got 0"},
      {"glass:nan", "--material: expected lambertian, metal[:FUZZ] or glass[:IOR], got glass:nan"},
  };
  for (const auto& [material, message] : cases) {
    const auto r = run_sphray("render -s " + path("one.xyz") + " --material " + material + " -o " +
                              path("out.png"));
    EXPECT_EQ(r.status, 2) << material << ": " << r.out;
    EXPECT_EQ(r.out, "sphray: " + message + " (see sphray --help)\n");
  }
  for (const std::string& scene : {std::string("three"), path("one.json")}) {
    write_text(path("one.json"), R"({"spheres": [{"center": [0, 0, 0], "radius": 1}]})");
    const auto r = run_sphray("render -s " + scene + " --material metal -o " + path("out.png"));
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_EQ(r.out, "sphray: --material applies to particle files (.xyz, .csv, .sphp), not to " +
                         scene + "\n");
  }
  for (const char* material : {"metal:0.2", "glass", "glass:1.33", "dielectric:2"}) {
    const auto r = run_sphray("render -q -m path --spp 1 -W 16 -H 9 -s " + path("one.xyz") +
                              " --material " + material + " -o " + path("ok.png"));
    EXPECT_EQ(r.status, 0) << material << ": " << r.out;
  }
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
      {"bad.ply",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n1 2 3\n",
       "",
       ":3: expected a property radius (or scale) in element vertex, or a radius given for the "
       "file (sphray render --radius R)"},
      // A list of 5 ints of which the file holds one.
      {"cut.ply",
       std::string("ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty uchar x\n"
                   "property uchar y\nproperty uchar z\nproperty float radius\nelement face 1\n"
                   "property list uchar int v\nend_header\n"
                   "\1\2\3\x3f\x80\0\0\5\0\0\0\1",
                   187),
       "", ": byte 187 (face 0): file ends, expected 16 more bytes"},
      {"bad.sphp", "SPHRAYP", "", ": truncated: 7 bytes, less than the 32-byte header"},
      {"nan.sphp",
       std::string("SPHRAYP\0\1\0\0\0\0\0\0\0\1\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0", 32) +
           std::string("\0\0\0\0\0\0\0\0\0\0\xc0\x7f\0\0\x80\x3f", 16),
       "",
       ": particle 0 (byte offset 32): expected a centre of at most 1e17 in magnitude and a "
       "radius in (0, 1e17], got (0, 0, nan) r 1"},
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
