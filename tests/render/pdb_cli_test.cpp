// `sphray render -s FILE.pdb`: PDB atoms render with their CPK colours, and a bad file is
// refused with exit status 2, one line naming the file and line, and the output untouched.
#include <gtest/gtest.h>

#include <array>
#include <string>

#include <stb/stb_image.h>

#include "command_run.hpp"
#include "test_files.hpp"

namespace {

using sphray::test::read_bytes;
using sphray::test::run_sphray;
using sphray::test::write_text;

class PdbCli : public sphray::test::ScratchDirTest {
 protected:
  PdbCli() : ScratchDirTest("sphray-pdb-cli-") {}
};

// One atom of element, framed to fill the middle of the image.
std::string one_atom(const std::string& element) {
  return "HEADER    ONE ATOM\n"
         "HETATM    1  X   UNK A   1       1.000   2.000   3.000  1.00  0.00          " +
         element + "\nEND\n";
}

// The centre pixel of a shaded 41x23 image of file.
std::array<int, 3> centre_of(const std::string& file, const std::string& image) {
  const auto r = run_sphray("render -m shaded --spp 1 -W 41 -H 23 -s " + file + " -o " + image);
  EXPECT_EQ(r.status, 0) << r.out;
  int w = 0, h = 0, channels = 0;
  stbi_uc* data = stbi_load(image.c_str(), &w, &h, &channels, 3);
  if (data == nullptr) return {-1, -1, -1};
  const stbi_uc* centre = data + 3 * (11 * 41 + 20);
  const std::array<int, 3> rgb{centre[0], centre[1], centre[2]};
  stbi_image_free(data);
  return rgb;
}

TEST_F(PdbCli, AtomsRenderInTheirElementsColours) {
  // Oxygen is Jmol's 0xFF0D0D: red, green and blue equal and far below it; carbon 0x909090 grey.
  write_text(path("o.pdb"), one_atom(" O"));
  const auto o = centre_of(path("o.pdb"), path("o.png"));
  EXPECT_GT(o[0], 100);
  EXPECT_EQ(o[1], o[2]);
  EXPECT_LT(2 * o[1], o[0]);
  write_text(path("c.pdb"), one_atom(" C"));
  const auto c = centre_of(path("c.pdb"), path("c.png"));
  EXPECT_GT(c[0], 50);
  EXPECT_EQ(c[0], c[1]);
  EXPECT_EQ(c[1], c[2]);
  // .ent, in any case, is the same format.
  write_text(path("O.ENT"), one_atom(" O"));
  EXPECT_EQ(run_sphray("render -q -W 16 -H 9 -s " + path("O.ENT") + " -o " + path("o.ppm")).status,
            0);
}

TEST_F(PdbCli, BadFilesAreRefusedAndTheOutputIsUntouched) {
  const std::pair<std::string, std::string> refusals[] = {
      {"HEADER    BAD\n"
       "ATOM      1  C   ALA A   1       1.000   2.0x0   3.000  1.00  0.00           C\n",
       ":2: expected columns 39-46 (y) to be a number, got \"   2.0x0\""},
      {"ATOM      1  C   ALA A   1       1.000   2.000   3.000  1.00  0.00           C\n"
       "ATOM      2  Q   ALA A   1       1.000   2.000   3.000  1.00  0.00           Q\n",
       ":2: expected an element symbol in columns 77-78 (element), got \"Q\""},
      {"REMARK   1 NOTHING HERE\n", ": expected ATOM or HETATM records, the file has none"},
  };
  for (const auto& [content, message] : refusals) {
    const std::string output = path("out.png");
    const std::string original = "not really a PNG, but it must survive";
    write_text(output, original);
    write_text(path("bad.pdb"), content);
    const auto r = run_sphray("render -s " + path("bad.pdb") + " -o " + output);
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_EQ(r.out, "sphray: " + path("bad.pdb") + message + "\n");
    EXPECT_EQ(read_bytes(output), original);
  }
}

}  // namespace
