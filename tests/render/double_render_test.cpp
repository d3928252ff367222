// Scenes traced in double (`sphray render --precision double`, docs/double.md "The command"):
// scene files and text particles keep their numbers as written, a camera given on the command
// line keeps its digits, and the image of a 1 mm sphere 36 km from the origin shows each pixel
// the sphere an exact (long double) pinhole camera and ray test say it shows, where float does
// not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "command/render_args.hpp"
#include "command_run.hpp"
#include "frame/scene_queries.hpp"
#include "sphray/particles/particles.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"
#include "test_files.hpp"
#include "test_pixels.hpp"

namespace {

using namespace sphray;
using namespace sphray::render;

// A 1 mm sphere resting on a 10 km ground, 36 km from the origin, the camera 6 mm beside it:
// at 3e4 float's spacing is 1/512 m, twice the small sphere's radius.
const std::string kMillimetreScene = R"({
  "width": 64, "height": 48,
  "camera": {"lookfrom": [29999.9958, 0.0015, 19999.9958], "lookat": [30000, 0.0008, 20000],
             "vfov": 40},
  "spheres": [
    {"center": [30000, -10000, 20000], "radius": 10000, "color": [0, 1, 0]},
    {"center": [30000, 0.001, 20000], "radius": 0.001, "color": [1, 0, 0]}
  ]
})";

TEST(DoubleScene, AFilesNumbersAreKeptAsWritten) {
  const Scene f = parse_scene(kMillimetreScene, "mm.json");
  EXPECT_FALSE(f.doubles.has_value());
  const Scene d = parse_scene(kMillimetreScene, "mm.json", Precision::float64);
  ASSERT_TRUE(d.doubles.has_value());
  ASSERT_EQ(d.doubles->spheres.size(), 2u);
  EXPECT_EQ(d.doubles->spheres.center(1), (Vec3d{30000, 0.001, 20000}));
  EXPECT_EQ(d.doubles->spheres.radius(1), 0.001);
  EXPECT_EQ(d.doubles->lookfrom, (Vec3d{29999.9958, 0.0015, 19999.9958}));
  EXPECT_EQ(d.doubles->lookat, (Vec3d{30000, 0.0008, 20000}));
  // The float members hold the same numbers rounded, as a float scene has them.
  EXPECT_EQ(d.spheres.center(1), f.spheres.center(1));
  EXPECT_EQ(d.camera.lookfrom, f.camera.lookfrom);
  EXPECT_NE(static_cast<double>(d.camera.lookfrom.x), d.doubles->lookfrom.x);
}

TEST(DoubleScene, TextAndPlyParticlesKeepTheirDigits) {
  const particles::Points text = particles::parse_points("30000.0001 2.5 -7 0.0001\n1 2 3 4\n",
                                                         "points.xyz", {std::nullopt, true});
  ASSERT_EQ(text.doubles.size(), 2u);
  EXPECT_EQ(text.doubles.center(0), (Vec3d{30000.0001, 2.5, -7}));
  EXPECT_EQ(text.doubles.radius(0), 0.0001);
  EXPECT_EQ(text.spheres.center(0).x, 30000.0001f);
  EXPECT_EQ(particles::parse_points("1 2 3 4\n", "points.xyz").doubles.size(), 0u);

  // A double property keeps its digits; a float property is a float, widened.
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty double y\n"
      "property float z\nproperty double radius\nend_header\n30000.0001 0.1 0.1 0.001\n";
  const particles::Points p = particles::parse_ply(ply, "p.ply", {std::nullopt, true});
  ASSERT_EQ(p.doubles.size(), 1u);
  EXPECT_EQ(p.doubles.center(0), (Vec3d{30000.0001, 0.1, static_cast<double>(0.1f)}));
  EXPECT_EQ(p.doubles.radius(0), 0.001);
}

TEST(DoubleScene, PresetsAreWidenedExactly) {
  SceneOptions options;
  options.precision = Precision::float64;
  const Scene s = load_scene_or_preset("three", options);
  ASSERT_TRUE(s.doubles.has_value());
  ASSERT_EQ(s.doubles->spheres.size(), s.spheres.size());
  for (std::uint32_t id = 0; id < s.spheres.size(); ++id) {
    EXPECT_EQ(s.doubles->spheres.center(id), vec3_cast<double>(s.spheres.center(id)));
    EXPECT_EQ(s.doubles->spheres.radius(id), static_cast<double>(s.spheres.radius(id)));
  }
  EXPECT_EQ(s.doubles->lookfrom, vec3_cast<double>(s.camera.lookfrom));
}

TEST(DoubleScene, ACameraOnTheCommandLineKeepsItsDigits) {
  Scene s = parse_scene(kMillimetreScene, "mm.json", Precision::float64);
  CameraArgs camera;
  camera.lookfrom = Vec3d{29999.9961, 0.0017, 19999.9961};
  apply_camera(camera, s);
  EXPECT_EQ(s.doubles->lookfrom, (Vec3d{29999.9961, 0.0017, 19999.9961}));
  EXPECT_EQ(s.doubles->lookat, (Vec3d{30000, 0.0008, 20000}));
  EXPECT_EQ(s.camera.lookfrom, vec3_cast<float>(*camera.lookfrom));

  // A camera that is a point in float but not in double is placed in double only.
  camera.lookfrom = Vec3d{30000.0002, 0.0008, 20000};
  apply_camera(camera, s);
  EXPECT_EQ(s.camera.lookfrom, s.camera.lookat);
  Scene f = parse_scene(kMillimetreScene, "mm.json");
  EXPECT_THROW(apply_camera(camera, f), SceneError);
}

// Which sphere the pixel centre (x, y) of a width x height image shows: a pinhole camera and
// the ray's roots in long double, written here from the book's construction. -1 for none,
// -2 for a ray within a relative 1e-6 of grazing a sphere (rounding may decide those).
int exact_sphere(const Scene& scene, int x, int y, int width, int height) {
  using L = long double;
  struct V {
    L x, y, z;
  };
  const auto sub = [](V a, V b) { return V{a.x - b.x, a.y - b.y, a.z - b.z}; };
  const auto dot = [](V a, V b) { return a.x * b.x + a.y * b.y + a.z * b.z; };
  const auto cross = [](V a, V b) {
    return V{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  };
  const auto unit = [&](V a) {
    const L n = std::sqrt(dot(a, a));
    return V{a.x / n, a.y / n, a.z / n};
  };
  const auto widen = [](Vec3d v) { return V{v.x, v.y, v.z}; };
  const V from = widen(scene.doubles->lookfrom), at = widen(scene.doubles->lookat);
  const V w = unit(sub(from, at));
  const V u = unit(cross(V{0, 1, 0}, w));
  const V v = cross(w, u);
  const L h = std::tan(static_cast<L>(scene.camera.vfov) * 3.14159265358979323846L / 360);
  const L s = (2 * (x + 0.5L) / width - 1) * h * width / height;
  const L t = (1 - 2 * (y + 0.5L) / height) * h;
  const V dir{-w.x + s * u.x + t * v.x, -w.y + s * u.y + t * v.y, -w.z + s * u.z + t * v.z};
  int best = -1;
  L best_t = INFINITY;
  for (std::uint32_t id = 0; id < scene.doubles->spheres.size(); ++id) {
    const V oc = sub(from, widen(scene.doubles->spheres.center(id)));
    const L r = scene.doubles->spheres.radius(id);
    const L a = dot(dir, dir), b = dot(oc, dir), c = dot(oc, oc) - r * r;
    const L disc = b * b - a * c;
    if (std::abs(disc) < 1e-6L * b * b) return -2;
    if (disc < 0) continue;
    const L near = (-b - std::sqrt(disc)) / a;
    if (near > 0 && near < best_t) best_t = near, best = static_cast<int>(id);
  }
  return best;
}

// The scene's size at one sample per pixel centre, in mode and precision.
RenderOptions frame_of(const Scene& scene, Mode mode, Precision precision) {
  RenderOptions options;
  options.mode = mode;
  options.width = scene.width;
  options.height = scene.height;
  options.spp = 1;
  options.precision = precision;
  return options;
}

// The sphere of each pixel in flat mode: pure green is sphere 0, pure red sphere 1.
int shown_sphere(const Image& image, int x, int y) {
  const std::uint8_t* p = &image.rgb[3 * (static_cast<std::size_t>(y) * image.width + x)];
  if (p[0] == 0 && p[1] == 255 && p[2] == 0) return 0;
  if (p[0] == 255 && p[1] == 0 && p[2] == 0) return 1;
  return -1;
}

TEST(DoubleRender, EveryPixelShowsTheSphereAnExactReferenceSays) {
  const Scene scene = parse_scene(kMillimetreScene, "mm.json", Precision::float64);
  const Image in_double =
      sphray::render::render(scene, frame_of(scene, Mode::flat, Precision::float64));
  const Image in_float =
      sphray::render::render(scene, frame_of(scene, Mode::flat, Precision::float32));

  int small = 0, checked = 0, double_wrong = 0, float_wrong = 0;
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      const int expected = exact_sphere(scene, x, y, scene.width, scene.height);
      if (expected == -2) continue;
      ++checked;
      small += expected == 1;
      double_wrong += shown_sphere(in_double, x, y) != expected;
      float_wrong += shown_sphere(in_float, x, y) != expected;
    }
  }
  EXPECT_GT(checked, scene.width * scene.height * 9 / 10);
  EXPECT_GT(small, 200);  // the small sphere fills a good part of the image
  EXPECT_EQ(double_wrong, 0);
  // What double is for: float misplaces a good share of the small sphere's pixels.
  EXPECT_GT(float_wrong, small / 10) << "float got " << float_wrong << " of " << checked;
}

TEST(DoubleRender, ShadowRaysLeaveTheSurfaceInDouble) {
  // Shaded mode's shadow rays from the ground around the small sphere: in double they start on
  // the ground (spawn()), so the ground is lit except in the small sphere's shadow, where a
  // relative offset of 1e-4 would have started them metres above it.
  const Scene scene = parse_scene(kMillimetreScene, "mm.json", Precision::float64);
  RenderStats stats;
  const Image image =
      sphray::render::render(scene, frame_of(scene, Mode::shaded, Precision::float64), {}, &stats);
  EXPECT_GT(stats.shadow_rays, 0u);
  // The ground's pixels at the bottom corners are lit (sun from above), those just below the
  // small sphere's contact in its shadow: darker.
  const auto grey = [&](int x, int y) {
    const std::uint8_t* p = &image.rgb[3 * (static_cast<std::size_t>(y) * image.width + x)];
    return p[0] + p[1] + p[2];
  };
  int shadowed = 0;
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      if (exact_sphere(scene, x, y, scene.width, scene.height) == 0 &&
          grey(x, y) < grey(0, scene.height - 1) / 2)
        ++shadowed;
    }
  }
  EXPECT_GT(shadowed, 20);
  EXPECT_LT(shadowed, scene.width * scene.height / 4);
}

TEST(DoubleRender, PathModeAndTheCallersQueriesRefuseDouble) {
  const Scene scene = make_preset("single");
  RenderOptions options;
  options.width = 8;
  options.height = 8;
  options.precision = Precision::float64;
  options.mode = Mode::path;
  EXPECT_THROW(sphray::render::render(scene, options), std::invalid_argument);
  options.mode = Mode::normals;
  const SceneQueries queries(scene.spheres, Accel::automatic);
  EXPECT_THROW(sphray::render::render(scene, queries, options), std::invalid_argument);
}

class DoubleCli : public sphray::test::ScratchDirTest {
 protected:
  DoubleCli() : ScratchDirTest("sphray-double-cli-") {}
};

TEST_F(DoubleCli, RefusesPathModeAndUnknownPrecisionsBeforeAnyWork) {
  sphray::test::write_text(path("out.png"), "kept");
  for (const std::string args : {"-m path --precision double", "--precision quad"}) {
    const auto r =
        sphray::test::run_sphray("render -q -s single " + args + " -o " + path("out.png"));
    EXPECT_EQ(r.status, 2) << args << ": " << r.out;
    EXPECT_NE(r.out.find("precision"), std::string::npos) << r.out;
    EXPECT_EQ(sphray::test::read_bytes(path("out.png")), "kept");
  }
}

TEST_F(DoubleCli, RendersAFileInDoubleAsTheLibraryDoes) {
  sphray::test::write_text(path("mm.json"), kMillimetreScene);
  const auto r =
      sphray::test::run_sphray("render -q -s " + path("mm.json") +
                               " -m flat --spp 1 --precision double -o " + path("out.png"));
  ASSERT_EQ(r.status, 0) << r.out;
  const Scene scene = parse_scene(kMillimetreScene, "mm.json", Precision::float64);
  const Image image =
      sphray::render::render(scene, frame_of(scene, Mode::flat, Precision::float64));
  const sphray::test::Pixels written = sphray::test::load_pixels(path("out.png"));
  ASSERT_EQ(written.rgb.size(), image.rgb.size());
  EXPECT_TRUE(std::equal(image.rgb.begin(), image.rgb.end(), written.rgb.begin()));
}

TEST_F(DoubleCli, ParticleFilesKeepTheirDigitsOrAreWidened) {
  SceneOptions options;
  options.precision = Precision::float64;
  sphray::test::write_text(path("p.xyz"), "30000.0001 2 3 0.5\n1 2 3 4\n");
  const Scene text = load_particle_scene(path("p.xyz"), options);
  ASSERT_TRUE(text.doubles.has_value());
  ASSERT_EQ(text.doubles->spheres.size(), 2u);
  EXPECT_EQ(text.doubles->spheres.center(0), (Vec3d{30000.0001, 2, 3}));
  EXPECT_EQ(text.doubles->lookfrom, vec3_cast<double>(text.camera.lookfrom));

  // A .sphp file holds floats: its doubles are those floats, widened.
  std::string bytes;
  particles::write_particle_file(
      [&bytes](const void* data, std::size_t size) {
        bytes.append(static_cast<const char*>(data), size);
      },
      path("p.sphp"), text.spheres.view());
  sphray::test::write_text(path("p.sphp"), bytes);
  const Scene binary = load_particle_scene(path("p.sphp"), options);
  ASSERT_TRUE(binary.doubles.has_value());
  ASSERT_EQ(binary.doubles->spheres.size(), 2u);
  for (std::uint32_t id = 0; id < 2; ++id)
    EXPECT_EQ(binary.doubles->spheres.center(id), vec3_cast<double>(binary.spheres.center(id)));
  EXPECT_NE(binary.doubles->spheres.center(0).x, 30000.0001);
  EXPECT_EQ(binary.doubles->lookat, vec3_cast<double>(binary.camera.lookat));
}

}  // namespace
