// Text points (.xyz, .csv): the forms a file may take, read as written; every refusal one line
// "FILE:LINE: expected ..., got ..."; a file larger than the reader's buffer read as the same
// text in memory; and the same hits from a file as from the spheres it was written from.
#include <charconv>

#include "particle_test_support.hpp"
#include "sphray/particles/particles.hpp"

namespace {

using sphray::particles::Points;
using sphray::particles::read_points;
using sphray::particles::test::expect_refused;
using sphray::particles::test::ParticleFileTest;

class TextPoints : public ParticleFileTest {
 protected:
  Points read(const std::string& name, const std::string& text,
              std::optional<float> radius = std::nullopt) {
    write(path(name), text);
    return read_points(path(name), {radius});
  }
};

TEST_F(TextPoints, WhitespaceColumnsCommentsAndBlankLines) {
  const Points p = read("a.xyz",
                        "# a comment, then a blank line\n"
                        "\n"
                        "1 2 3 0.5\n"
                        "  -1\t-2   -3e0 2   # trailing comment\r\n"
                        "+4 5 6 .25");  // a '+' sign, no final newline
  ASSERT_EQ(p.spheres.size(), 3u);
  EXPECT_TRUE(p.colors.empty());
  EXPECT_EQ(p.spheres.center(1).z, -3.0f);
  EXPECT_EQ(p.spheres.radius(1), 2.0f);
  EXPECT_EQ(p.spheres.radius(2), 0.25f);
}

TEST_F(TextPoints, CsvWithAHeaderInAnyOrderAndByteColours) {
  const Points p = read("a.csv",
                        "\xEF\xBB\xBFRadius, x,y,z,red,green,blue\n"
                        "0.5, 1,2,3, 255,0,51\n"
                        "1,   0,0,0, 0,255,0\n");
  ASSERT_EQ(p.spheres.size(), 2u);
  EXPECT_EQ(p.spheres.center(0).x, 1.0f);
  EXPECT_EQ(p.spheres.radius(0), 0.5f);
  ASSERT_EQ(p.colors.size(), 2u);
  EXPECT_EQ(p.colors[0].x, 1.0f);
  EXPECT_EQ(p.colors[0].z, 0.2f);  // 51 / 255
  EXPECT_EQ(p.colors[1].y, 1.0f);
}

TEST_F(TextPoints, UnitColoursAndARadiusGivenForTheFile) {
  const Points p = read("a.xyz", "x y z red green blue\n0 0 0 0.5 1 0\n1 1 1 0 0 0.25\n", 0.75f);
  ASSERT_EQ(p.spheres.size(), 2u);
  EXPECT_EQ(p.spheres.radius(1), 0.75f);
  EXPECT_EQ(p.colors[0].x, 0.5f);  // all in [0, 1]: read as they are
  EXPECT_EQ(p.colors[1].z, 0.25f);
  // Without a header, the column count says which columns there are.
  EXPECT_EQ(read("b.xyz", "1 2 3\n", 2.0f).spheres.radius(0), 2.0f);
  const Points seven = read("c.xyz", "1 2 3 4 0 1 0\n");
  EXPECT_EQ(seven.spheres.radius(0), 4.0f);
  EXPECT_EQ(seven.colors[0].y, 1.0f);
  // A radius column wins over the radius given.
  EXPECT_EQ(read("d.xyz", "1 2 3 4\n", 2.0f).spheres.radius(0), 4.0f);
}

struct Refusal {
  std::string text;
  std::string message;  // after "FILE"
  std::optional<float> radius = std::nullopt;
};

TEST_F(TextPoints, BadFilesAreRefusedNamingTheLine) {
  const Refusal refusals[] = {
      {"1 2 3 4\n1 2 3\n", ":2: expected 4 columns, as the first line has, got 3"},
      {"1 2 3 4 5\n",
       ":1: expected 3, 4, 6 or 7 columns (x y z [radius] [red green blue]) or a "
       "header naming them, got 5"},
      {"1 2 3\n",
       ":1: expected a radius column, or a radius given for the file (sphray render "
       "--radius R)"},
      {"# c\nx y z\n1 2 3\n",
       ":2: expected a radius column, or a radius given for the file "
       "(sphray render --radius R)"},
      {"1 2 3 0.5\n1 two 3 0.5\n", ":2: expected column 2 (y) to be a number, got \"two\""},
      {"1 2 3 -0.5\n", ":1: expected column 4 (radius) to be positive, got \"-0.5\""},
      {"1 2 3 0\n", ":1: expected column 4 (radius) to be positive, got \"0\""},
      {"1 2 +-3 1\n", ":1: expected column 3 (z) to be a number, got \"+-3\""},
      {"1 nan 3 1\n", ":1: expected column 2 (y) to be finite, got \"nan\""},
      {"1e39 2 3 1\n", ":1: expected column 1 (x) within float's range, got \"1e39\""},
      {"1 2 3 1e-50\n", ":1: expected column 4 (radius) within float's range, got \"1e-50\""},
      {"1 2 1e18 1\n", ":1: expected column 3 (z) at most 1e17 in magnitude, got \"1e18\""},
      {"1 2 3 1 0 0 256\n", ":1: expected column 7 (blue) in [0, 1] or [0, 255], got \"256\""},
      {"1,2,3,1\n1,2,,1\n", ":2: expected column 3 (z) to be a number, got \"\""},
      {"x,y,z,colour\n",
       ":1: expected column names x, y, z, radius (or r), red, green, blue, got "
       "\"colour\""},
      {"x y z x\n", ":1: expected each column named once, got \"x\" twice"},
      {"x y radius\n", ":1: expected columns named x, y and z in the header"},
      {"x y z r red\n", ":1: expected red, green and blue columns together, or none"},
      {"1 2 3 1\n1 2 \x01\xff 1\n", ":2: expected column 3 (z) to be a number, got \"\\x01\\xff\""},
      {"# only a comment\n\n", ": expected particles, the file has none"},
      {"", ": expected particles, the file has none"},
      {"1 2 3\n",
       ": expected the radius given for the file to be positive and at most 1e17, got -1", -1.0f},
      {"1 2 3 1\n" + std::string(5000, ' ') + "\n", ":2: expected lines of at most 4096 bytes"},
  };
  for (const Refusal& refusal : refusals) {
    const auto file = path("bad.xyz");
    write(file, refusal.text);
    expect_refused([&] { read_points(file, {refusal.radius}); }, file.string() + refusal.message);
    // The same text in memory gives the same message, its source standing for the file.
    expect_refused([&] { sphray::particles::parse_points(refusal.text, "mem", {refusal.radius}); },
                   "mem" + refusal.message);
  }
  expect_refused([&] { read_points(dir_); },
                 dir_.string() + ": expected a particle file, got a directory");
  expect_refused([&] { sphray::particles::read_particle_file(path("a.obj")); },
                 path("a.obj").string() +
                     ": expected a particle file ending in .sphp, .xyz, .csv, .ply, .pdb or .ent");
}

// Floats written shortest-exact (std::to_chars) read back as the same bits.
std::string text_of(const sphray::SphereSoA& spheres, char separator) {
  std::string text = "# x y z r\n";
  for (std::uint32_t i = 0; i < spheres.size(); ++i) {
    const sphray::Vec3 c = spheres.center(i);
    for (float v : {c.x, c.y, c.z, spheres.radius(i)}) {
      char buffer[32];
      text.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
      text += separator;
    }
    text.back() = '\n';
  }
  return text;
}

TEST_F(TextPoints, TheSameHitsFromAFileAsFromTheSpheresInMemory) {
  // 20,000 lines: many times the reader's 64 KiB buffer, lines straddling its refills.
  const sphray::SphereSoA spheres = sphray::particles::test::random_spheres(20000, 5);
  for (const char* name : {"cloud.xyz", "cloud.csv"}) {
    const std::string text = text_of(spheres, name == std::string("cloud.csv") ? ',' : ' ');
    ASSERT_GT(text.size(), 4u << 16);
    write(path(name), text);
    const Points p = sphray::particles::read_particle_file(path(name));
    ASSERT_EQ(p.spheres.size(), spheres.size());
    for (std::uint32_t i = 0; i < spheres.size(); ++i) {
      ASSERT_EQ(p.spheres.center(i).y, spheres.center(i).y) << name << " particle " << i;
      ASSERT_EQ(p.spheres.radius(i), spheres.radius(i)) << name << " particle " << i;
    }
    sphray::particles::test::expect_same_hits(p.spheres, spheres);
  }
}

TEST_F(TextPoints, ALongLineIsRefusedWhereverTheBufferEnds) {
  // A line that would straddle a refill of the buffer is measured across it.
  std::string text;
  for (int i = 0; i < 4000; ++i)
    text += "1 2 3 0.5\n";
  text += std::string(6000, '1') + "\n";
  write(path("long.xyz"), text);
  expect_refused([&] { read_points(path("long.xyz")); },
                 path("long.xyz").string() + ":4001: expected lines of at most 4096 bytes");
}

}  // namespace
