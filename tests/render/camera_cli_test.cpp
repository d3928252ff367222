// `--lookfrom`, `--lookat`, `--vup` and `--vfov` on `sphray render` (and bench): the scene's own
// camera given on the command line changes no byte, each option alone changes only its part (the
// same image as a scene file with that camera), a moved camera puts a sphere where the pinhole
// model computed here says, and a camera that cannot be placed is refused with one line.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <stb/stb_image.h>

#include "command_run.hpp"
#include "test_files.hpp"
#include "test_pixels.hpp"

namespace {

using sphray::test::read_bytes;
using sphray::test::run_sphray;
using sphray::test::write_text;

class CameraCli : public sphray::test::ScratchDirTest {
 protected:
  CameraCli() : ScratchDirTest("sphray-camera-cli-") {}

  // The image `sphray render -q <args> -o out.ppm` writes, as its bytes.
  std::string render(const std::string& args, const std::string& name = "out.ppm") {
    const auto r = run_sphray("render -q " + args + " -o " + path(name));
    EXPECT_EQ(r.status, 0) << args << ": " << r.out;
    return read_bytes(path(name));
  }
};

using sphray::test::load_pixels;
using sphray::test::Pixels;

TEST_F(CameraCli, TheScenesOwnCameraGivenOnTheCommandLineChangesNoByte) {
  const std::pair<const char*, const char*> cases[] = {
      {"single", "--lookfrom 0,0,0 --lookat 0,0,-1 --vup 0,1,0 --vfov 90"},
      {"three", "--lookfrom 0.5,1.5,7 --lookat 0,-0.2,0.3 --vfov 32"},
      {"rtiow-final", "--lookfrom 13,2,3 --lookat 0,0,0 --vfov 20"},
  };
  for (const auto& [scene, camera] : cases) {
    for (const char* mode : {"normals", "depth", "shaded", "path"}) {
      const std::string args = std::string("-s ") + scene + " -m " + mode + " -W 64 -H 36 --spp 2";
      EXPECT_EQ(render(args + " " + camera, "given.ppm"), render(args, "default.ppm"))
          << scene << " in " << mode << " mode";
    }
  }
}

TEST_F(CameraCli, EachOptionAloneChangesOnlyItsPartOfTheScenesCamera) {
  // single's sphere and camera as a scene file, with one part of the camera changed each time.
  const std::string sphere =
      R"("spheres": [{"center": [0, 0, -1], "radius": 0.5, "color": [1, 0, 0]}])";
  const std::pair<const char*, const char*> cases[] = {
      {"--lookfrom 0.3,0.2,0.5", R"("lookfrom": [0.3, 0.2, 0.5], "lookat": [0, 0, -1])"},
      {"--lookat 0.2,0.1,-1", R"("lookfrom": [0, 0, 0], "lookat": [0.2, 0.1, -1])"},
      {"--vup 1,1,0", R"("lookfrom": [0, 0, 0], "lookat": [0, 0, -1], "vup": [1, 1, 0])"},
      {"--vfov 45", R"("lookfrom": [0, 0, 0], "lookat": [0, 0, -1], "vfov": 45)"},
  };
  const std::string single = render("-s single -W 64 -H 36 --spp 1", "single.ppm");
  for (const auto& [option, camera] : cases) {
    write_text(path("scene.json"), std::string("{\"camera\": {") + camera + "}, " + sphere + "}");
    const std::string args = " -W 64 -H 36 --spp 1";
    const std::string moved = render("-s single " + std::string(option) + args, "moved.ppm");
    EXPECT_EQ(moved, render("-s " + path("scene.json") + args, "file.ppm")) << option;
    EXPECT_NE(moved, single) << option;
  }
}

// The pixel the point p projects to, for a camera on the +z axis at distance `distance` looking
// at the origin with y up (the book's pinhole, written out here): x right, y down, in pixels.
std::pair<double, double> project(double px, double py, double pz, double distance,
                                  double vfov_degrees, int width, int height) {
  const double half = std::tan(vfov_degrees * std::numbers::pi / 360.0);
  const double pixel = 2.0 * half / height;  // the viewport at distance 1, square pixels
  const double depth = distance - pz;
  return {width / 2.0 + px / depth / pixel, height / 2.0 - py / depth / pixel};
}

TEST_F(CameraCli, AMovedCameraPutsASphereWhereThePinholeModelSays) {
  // One red sphere off the axis (flat mode paints it its colour); the particle file's own
  // framing looks straight at it.
  write_text(path("one.xyz"), "0.5 0.25 0 0.2 1 0 0\n");
  const std::string base = "-s " + path("one.xyz") + " -m flat --spp 1 -W 101 -H 101";
  render(base, "framed.png");
  render(base + " --lookfrom 0,0,10 --lookat 0,0,0 --vfov 20", "moved.png");
  const Pixels before = load_pixels(path("framed.png")), after = load_pixels(path("moved.png"));
  ASSERT_EQ(after.width, 101);
  const auto red = [](const int* p) { return p[0] == 255 && p[1] == 0 && p[2] == 0; };
  EXPECT_TRUE(red(before.at(50, 50)));  // framed: the sphere at the image centre
  EXPECT_FALSE(red(after.at(50, 50)));  // moved: the origin, which the sphere misses
  const auto [x, y] = project(0.5, 0.25, 0, 10, 20, 101, 101);
  EXPECT_TRUE(red(after.at(static_cast<int>(x), static_cast<int>(y)))) << x << ", " << y;
  // Its radius projects to about 5.7 pixels: 8 pixels away on each side is sky.
  for (const auto& [dx, dy] : {std::pair{8, 0}, {-8, 0}, {0, 8}, {0, -8}}) {
    EXPECT_FALSE(red(after.at(static_cast<int>(x) + dx, static_cast<int>(y) + dy)))
        << dx << ", " << dy;
  }
}

TEST_F(CameraCli, CamerasThatCannotBePlacedAreRefusedWithOneLine) {
  const std::string vector_expected =
      ": expected X,Y,Z: three finite numbers of at most 1e17 in magnitude, got ";
  const std::pair<std::string, std::string> cases[] = {
      {"--lookfrom 1,2", "--lookfrom" + vector_expected + "1,2 (see sphray --help)"},
      {"--lookfrom 1,2,3,4", "--lookfrom" + vector_expected + "1,2,3,4 (see sphray --help)"},
      {"--lookat 1,2,nan", "--lookat" + vector_expected + "1,2,nan (see sphray --help)"},
      {"--vup 0,inf,0", "--vup" + vector_expected + "0,inf,0 (see sphray --help)"},
      {"--lookat 1,x,2", "--lookat" + vector_expected + "1,x,2 (see sphray --help)"},
      {"--lookfrom 1e18,0,0", "--lookfrom" + vector_expected + "1e18,0,0 (see sphray --help)"},
      {"--vfov 0", "--vfov: expected degrees in (0, 180), got 0 (see sphray --help)"},
      {"--vfov 180", "--vfov: expected degrees in (0, 180), got 180 (see sphray --help)"},
      {"--vfov nan", "--vfov: expected degrees in (0, 180), got nan (see sphray --help)"},
      {"--lookat 0,0,0",
       "--lookat with the camera of single: expected lookfrom and lookat to differ"},
      {"--lookfrom 2,0,0 --lookat 2,0,0",
       "--lookfrom, --lookat with the camera of single: expected lookfrom and lookat to differ"},
      {"--vup 0,0,1",
       "--vup with the camera of single: expected vup not parallel to the view direction"},
      {"--lookfrom 0,5,-1",
       "--lookfrom with the camera of single: expected vup not parallel to the view direction"},
  };
  for (const auto& [options, message] : cases) {
    for (const char* command : {"render", "bench --seconds 0.01"}) {
      // render writes an image, bench (refused before any row) its --json file.
      const bool render = std::string(command) == "render";
      const std::string output = path(render ? "out.png" : "out.json");
      write_text(output, "untouched");
      const auto r = run_sphray(std::string(command) + " -s single " + options +
                                (render ? " -o " : " --json ") + output);
      EXPECT_EQ(r.status, 2) << command << " " << options << ": " << r.out;
      EXPECT_EQ(r.out, "sphray: " + message + "\n") << command << " " << options;
      EXPECT_EQ(read_bytes(output), "untouched");
    }
  }
}

}  // namespace
