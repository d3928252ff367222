// PDB atoms (.pdb, .ent): ATOM and HETATM records of the first model read from their fixed
// columns, each atom its element's van der Waals radius and CPK colour (the numbers below are
// written out from Bondi 1964 and Jmol's colour table, not taken from the reader), other
// records ignored; every refusal one line "FILE:LINE: expected ..., got ...".
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "particle_test_support.hpp"
#include "sphray/particles/particles.hpp"

namespace {

using sphray::Vec3;
using sphray::particles::parse_pdb;
using sphray::particles::Points;
using sphray::particles::read_pdb;
using sphray::particles::test::expect_refused;
using sphray::particles::test::ParticleFileTest;

class Pdb : public ParticleFileTest {
 protected:
  Points read(const std::string& name, const std::string& text) {
    write(path(name), text);
    return read_pdb(path(name));
  }
};

// A colour of Jmol's table, 0-255 per channel, as the reader gives it: in [0, 1].
Vec3 rgb(int r, int g, int b) {
  return {static_cast<float>(r) / 255.0f, static_cast<float>(g) / 255.0f,
          static_cast<float>(b) / 255.0f};
}

void expect_atom(const Points& p, std::uint32_t i, Vec3 center, float radius, Vec3 color) {
  SCOPED_TRACE("atom " + std::to_string(i));
  EXPECT_EQ(p.spheres.center(i).x, center.x);
  EXPECT_EQ(p.spheres.center(i).y, center.y);
  EXPECT_EQ(p.spheres.center(i).z, center.z);
  EXPECT_EQ(p.spheres.radius(i), radius);
  EXPECT_EQ(p.colors[i].x, color.x);
  EXPECT_EQ(p.colors[i].y, color.y);
  EXPECT_EQ(p.colors[i].z, color.z);
}

// Water, a haem iron, ammonia's nitrogen (its element in lower case) and a chloride ion; the
// second hydrogen and the chloride have blank element columns, so their names say what they are.
// Records of every other kind, and the second model, are ignored.
const char kWater[] =
    "HEADER    WATER AND FRIENDS\r\n"
    "REMARK   1 NOT AN ATOM 1.000 2.000 3.000\n"
    "MODEL        1\n"
    "ATOM      1  O   HOH A   1       0.000   0.000   0.000  1.00  0.00           O\n"
    "ATOM      2  H1  HOH A   2       0.757   0.586   0.000  1.00  0.00           H\r\n"
    "ATOM      3  H2  HOH A   3      -0.757   0.586   0.000  1.00  0.00            \n"
    "TER       4      HOH A   3\n"
    "HETATM    4 FE   HEM A   4      10.000  -5.500   2.250  1.00  0.00          FE\n"
    "HETATM    5  N   NH3 A   5       1.000   2.000   3.000  1.00  0.00           n\n"
    "HETATM    6 CL    CL A   6      -1.500   0.000   1.000  1.00  0.00\n"
    "CONECT    1    2    3\n"
    "ENDMDL\n"
    "MODEL        2\n"
    "ATOM      1  C   XXX A   7       9.000   9.000   9.000  1.00  0.00           C\n"
    "ATOM      2  this line would be refused, were it read\n"
    "ENDMDL\n";

TEST_F(Pdb, AtomsOfTheFirstModelWithTheirRadiiAndColours) {
  const Points p = read("water.pdb", kWater);
  ASSERT_EQ(p.spheres.size(), 6u);
  ASSERT_EQ(p.colors.size(), 6u);
  const Vec3 white = rgb(255, 255, 255);
  expect_atom(p, 0, {0, 0, 0}, 1.52f, rgb(255, 13, 13));               // O, 0xFF0D0D
  expect_atom(p, 1, {0.757f, 0.586f, 0}, 1.20f, white);                // H
  expect_atom(p, 2, {-0.757f, 0.586f, 0}, 1.20f, white);               // H, from " H2 "
  expect_atom(p, 3, {10.0f, -5.5f, 2.25f}, 2.00f, rgb(224, 102, 51));  // Fe: no Bondi radius
  expect_atom(p, 4, {1, 2, 3}, 1.55f, rgb(48, 80, 248));               // N, 0x3050F8
  expect_atom(p, 5, {-1.5f, 0, 1}, 1.75f, rgb(31, 240, 31));           // Cl, from "CL  "
  // The same text in memory, and the file through the extension dispatch, in any case.
  EXPECT_EQ(parse_pdb(kWater, "mem").spheres.size(), 6u);
  write(path("WATER.ENT"), kWater);
  EXPECT_TRUE(sphray::particles::is_particle_file(path("WATER.ENT")));
  EXPECT_TRUE(sphray::particles::is_particle_file("a.Pdb"));
  EXPECT_EQ(sphray::particles::read_particle_file(path("WATER.ENT")).spheres.radius(3), 2.00f);
}

TEST_F(Pdb, ElementsGuessedFromAtomNamesAsCommonReadersDo) {
  // name (columns 13-16) -> radius of the element it names, element columns blank or absent
  const std::pair<const char*, float> names[] = {
      {" CA ", 1.70f},  // column 13 blank: the letter in column 14, an alpha carbon
      {"CA  ", 2.31f},  // a two-letter name from column 13: calcium (Mantina 2009)
      {"1HB ", 1.20f},  // a digit in column 13: the letter after it
      {"HG21", 1.20f},  // a four-character hydrogen name, not mercury
      {"HG  ", 1.55f},  // mercury
      {"C1A ", 1.70f},  // "C1" is no element: column 13 alone
      {" OXT", 1.52f},
  };
  for (const auto& [name, radius] : names) {
    const std::string line =
        std::string("ATOM      1 ") + name + " ALA A   1       1.000   2.000   3.000";
    const Points p = parse_pdb(line, "mem");
    ASSERT_EQ(p.spheres.size(), 1u) << name;
    EXPECT_EQ(p.spheres.radius(0), radius) << name;
  }
  // "ATOM" whose serial overflowed into columns 5-6 is still an atom; "ATOMS" is not.
  EXPECT_EQ(
      parse_pdb("ATOM123456  C   ALA A   1       1.000   2.000   3.000  1.00  0.00           C\n"
                "ATOMS is not a record of the format\n",
                "mem")
          .spheres.size(),
      1u);
}

struct Refusal {
  std::string text;
  std::string message;  // after "FILE"
};

TEST_F(Pdb, BadFilesAreRefusedNamingTheLine) {
  const std::string header = "HEADER    BAD\n";
  const Refusal refusals[] = {
      {header + "ATOM      1  C   ALA A   1       1.000   abc     3.000  1.00  0.00           C\n",
       ":2: expected columns 39-46 (y) to be a number, got \"   abc  \""},
      {header + "ATOM      1  C   ALA A   1       1.000   2.000\n",
       ":2: expected columns 47-54 (z) to be a number, got \"\""},
      {header + "ATOM      1  C   ALA A   1         nan   2.000   3.000  1.00  0.00           C\n",
       ":2: expected columns 31-38 (x) to be finite, got \"     nan\""},
      {header + "ATOM      1  C   ALA A   1        1e18   2.000   3.000  1.00  0.00           C\n",
       ":2: expected columns 31-38 (x) at most 1e17 in magnitude, got \"    1e18\""},
      {header + "HETATM    1  C   ALA A   1       1.000   2.000   3.000  1.00  0.00           C\n" +
           "HETATM    2  X   UNK A   1       1.000   2.000   3.000  1.00  0.00          XX\n",
       ":3: expected an element symbol in columns 77-78 (element), got \"XX\""},
      {header + "HETATM    1  ?   UNK A   1       1.000   2.000   3.000\n",
       ":2: expected an element symbol in columns 77-78 (element) or at the start of columns "
       "13-16 (atom name), got \" ?  \""},
      {header + "REMARK " + std::string(5000, 'x') + "\n",
       ":2: expected lines of at most 4096 bytes"},
      {header + "REMARK   no atoms at all\nEND\n",
       ": expected ATOM or HETATM records, the file has none"},
      {"", ": expected ATOM or HETATM records, the file has none"},
  };
  for (const Refusal& refusal : refusals) {
    const auto file = path("bad.pdb");
    write(file, refusal.text);
    expect_refused([&] { read_pdb(file); }, file.string() + refusal.message);
    expect_refused([&] { parse_pdb(refusal.text, "mem"); }, "mem" + refusal.message);
  }
  expect_refused([&] { read_pdb(dir_); },
                 dir_.string() + ": expected a particle file, got a directory");
}

TEST_F(Pdb, AFileLargerThanTheBufferReadsAsTheSameTextInMemory) {
  // 20,000 atoms, 1.6 MB: lines straddle the reader's buffer refills.
  std::string text;
  for (int i = 0; i < 20000; ++i) {
    char line[96];
    std::snprintf(line, sizeof line,
                  "ATOM  %5d  C   ALA A   1    %8.3f%8.3f%8.3f  1.00  0.00           C\n",
                  i % 100000, 0.001 * i, -0.002 * i, 0.5 * (i % 7));
    text += line;
  }
  const Points from_file = read("big.pdb", text);
  const Points from_memory = parse_pdb(text, "mem");
  ASSERT_EQ(from_file.spheres.size(), 20000u);
  for (std::uint32_t i = 0; i < 20000; i += 997) {
    EXPECT_EQ(from_file.spheres.center(i).x, from_memory.spheres.center(i).x);
    EXPECT_EQ(from_file.spheres.center(i).y, from_memory.spheres.center(i).y);
  }
  EXPECT_EQ(from_file.spheres.center(19999).x, 19.999f);
  sphray::particles::test::expect_same_hits(from_file.spheres, from_memory.spheres);
}

// docs/gallery/make_c60_pdb.py's fullerene: 60 carbons, each at 1.4 angstroms from three others.
TEST_F(Pdb, TheGalleryFullerene) {
  if (!std::filesystem::exists("/usr/bin/python3")) GTEST_SKIP() << "no /usr/bin/python3";
  const std::string command =
      std::string("/usr/bin/python3 ") + SPHRAY_C60_SCRIPT + " " + path("c60.pdb").string();
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const Points p = read_pdb(path("c60.pdb"));
  ASSERT_EQ(p.spheres.size(), 60u);
  for (std::uint32_t i = 0; i < 60; ++i) {
    EXPECT_EQ(p.spheres.radius(i), 1.70f);      // carbon, Bondi
    EXPECT_EQ(p.colors[i].x, 144.0f / 255.0f);  // 0x909090
    const Vec3 c = p.spheres.center(i);
    EXPECT_NEAR(std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z), 3.47, 0.01);  // 0.7 sqrt(1 + 9 phi^2)
    int bonded = 0;
    for (std::uint32_t j = 0; j < 60; ++j) {
      const Vec3 d = p.spheres.center(j) - c;
      bonded += std::abs(std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z) - 1.4f) < 0.003f;
    }
    EXPECT_EQ(bonded, 3) << "atom " << i;
  }
}

}  // namespace
