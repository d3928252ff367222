// Presets and JSON scenes. Expected values are the issue's numbers, worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "sphray/render/scene.hpp"

namespace sphray::render {
namespace {

void expect_sphere(const Scene& s, std::uint32_t id, Vec3 center, float radius) {
  EXPECT_EQ(s.spheres.center(id), center) << "sphere " << id;
  EXPECT_EQ(s.spheres.radius(id), radius) << "sphere " << id;
}

TEST(Presets, SingleIsTheBooksChapterFive) {
  Scene s = make_preset("single");
  ASSERT_EQ(s.spheres.size(), 1u);
  expect_sphere(s, 0, {0, 0, -1}, 0.5f);
  EXPECT_EQ(s.camera.lookfrom, (Vec3{0, 0, 0}));
  EXPECT_EQ(s.camera.vfov, 90.0f);  // viewport 2 high at focal length 1: 2 * atan(1)
  EXPECT_EQ(s.width, 400);
  EXPECT_EQ(s.height, 225);
}

TEST(Presets, ThreeHasTheIssuesSpheres) {
  Scene s = make_preset("three");
  ASSERT_EQ(s.spheres.size(), 3u);
  expect_sphere(s, 0, {0, 0, 0}, 1.0f);
  expect_sphere(s, 1, {-2.2f, -0.3f, 0.5f}, 0.7f);
  expect_sphere(s, 2, {2, -0.5f, 1}, 0.5f);
  EXPECT_GT(s.colors[0].x, s.colors[0].z);  // red
  EXPECT_GT(s.colors[1].z, s.colors[1].x);  // blue
  EXPECT_GT(s.colors[2].y, s.colors[2].x);  // green
}

TEST(Presets, RtiowFinalHasTheBooksLayout) {
  Scene s = make_preset("rtiow-final");
  std::size_t n = s.spheres.size();
  ASSERT_GE(n, 4u);
  ASSERT_LE(n, 1u + 22u * 22u + 3u);
  ASSERT_EQ(s.colors.size(), n);
  expect_sphere(s, 0, {0, -1000, 0}, 1000.0f);
  expect_sphere(s, static_cast<std::uint32_t>(n - 3), {0, 1, 0}, 1.0f);
  expect_sphere(s, static_cast<std::uint32_t>(n - 2), {-4, 1, 0}, 1.0f);
  expect_sphere(s, static_cast<std::uint32_t>(n - 1), {4, 1, 0}, 1.0f);
  for (std::uint32_t id = 1; id + 3 < n; ++id) {
    Vec3 c = s.spheres.center(id);
    EXPECT_EQ(s.spheres.radius(id), 0.2f);
    EXPECT_EQ(c.y, 0.2f);
    EXPECT_GE(c.x, -11.0f);
    EXPECT_LT(c.x, 11.0f);
    EXPECT_GE(c.z, -11.0f);
    EXPECT_LT(c.z, 11.0f);
    // The book keeps the grid clear of the metal sphere's spot.
    EXPECT_GT(std::hypot(c.x - 4.0f, c.z), 0.9f);
  }
  EXPECT_EQ(s.camera.lookfrom, (Vec3{13, 2, 3}));
  EXPECT_EQ(s.camera.lookat, (Vec3{0, 0, 0}));
  EXPECT_EQ(s.camera.vfov, 20.0f);
  EXPECT_EQ(s.camera.defocus_angle, 0.6f);  // the book's cover camera
  EXPECT_EQ(s.camera.focus_dist, 10.0f);
}

// The book's materials: the ground grey Lambertian, the three large spheres glass (1.5), brown
// Lambertian and polished metal, and the grid drawn 80% diffuse, 15% metal, 5% glass (the 480-odd
// draws put each share within a few points of that).
TEST(Presets, RtiowFinalHasTheBooksMaterials) {
  Scene s = make_preset("rtiow-final");
  const std::size_t n = s.spheres.size();
  ASSERT_EQ(s.materials.size(), n);
  EXPECT_EQ(s.materials[0].kind, MaterialKind::lambertian);
  EXPECT_EQ(s.materials[0].albedo, (Vec3{0.5f, 0.5f, 0.5f}));
  EXPECT_EQ(s.materials[n - 3].kind, MaterialKind::dielectric);
  EXPECT_EQ(s.materials[n - 3].ior, 1.5f);
  EXPECT_EQ(s.materials[n - 2].kind, MaterialKind::lambertian);
  EXPECT_EQ(s.materials[n - 2].albedo, (Vec3{0.4f, 0.2f, 0.1f}));
  EXPECT_EQ(s.materials[n - 1].kind, MaterialKind::metal);
  EXPECT_EQ(s.materials[n - 1].albedo, (Vec3{0.7f, 0.6f, 0.5f}));
  EXPECT_EQ(s.materials[n - 1].fuzz, 0.0f);
  std::size_t count[3] = {0, 0, 0};
  for (std::size_t id = 1; id + 3 < n; ++id) {
    const Material& m = s.materials[id];
    ++count[static_cast<int>(m.kind)];
    if (m.kind == MaterialKind::metal) {
      EXPECT_GE(m.albedo.x, 0.5f);
      EXPECT_GE(m.fuzz, 0.0f);
      EXPECT_LT(m.fuzz, 0.5f);
    }
    if (m.kind == MaterialKind::dielectric) {
      EXPECT_EQ(m.ior, 1.5f);
    }
  }
  const double grid = static_cast<double>(n - 4);
  EXPECT_NEAR(static_cast<double>(count[0]) / grid, 0.80, 0.06);
  EXPECT_NEAR(static_cast<double>(count[1]) / grid, 0.15, 0.05);
  EXPECT_NEAR(static_cast<double>(count[2]) / grid, 0.05, 0.03);
}

TEST(Presets, AreTheSameEveryTime) {
  for (const char* name : {"rtiow-final", "random:1000"}) {
    Scene a = make_preset(name), b = make_preset(name);
    ASSERT_EQ(a.spheres.size(), b.spheres.size());
    for (std::uint32_t i = 0; i < a.spheres.size(); ++i) {
      ASSERT_EQ(a.spheres.center(i), b.spheres.center(i));
      ASSERT_EQ(a.spheres.radius(i), b.spheres.radius(i));
      ASSERT_EQ(a.colors[i], b.colors[i]);
    }
  }
}

TEST(Presets, RandomFillsTheBoxAndIsSeenFromOutside) {
  Scene s = make_preset("random:5000");
  ASSERT_EQ(s.spheres.size(), 5000u);
  float base = 50.0f / std::cbrt(5000.0f);
  for (std::uint32_t i = 0; i < 5000; ++i) {
    Vec3 c = s.spheres.center(i);
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(c[k], -50.0f);
      EXPECT_LT(c[k], 50.0f);
    }
    EXPECT_GE(s.spheres.radius(i), 0.5f * base * 0.999f);
    EXPECT_LE(s.spheres.radius(i), 1.5f * base * 1.001f);
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(s.colors[i][k], 0.0f);
      EXPECT_LE(s.colors[i][k], 1.0f);
    }
  }
  Vec3 from = s.camera.lookfrom;
  EXPECT_GT(std::max({std::abs(from.x), std::abs(from.y), std::abs(from.z)}), 50.0f);
  EXPECT_EQ(s.camera.lookat, (Vec3{0, 0, 0}));
}

TEST(Presets, RandomOfAMillionIsQuickToMake) {
  Scene s = make_preset("random:1000000");
  EXPECT_EQ(s.spheres.size(), 1000000u);
  EXPECT_EQ(s.colors.size(), 1000000u);
}

TEST(Presets, UnknownNamesAndBadCountsAreRefused) {
  for (const char* name : {"", "singel", "random:", "random:0", "random:-3", "random:12x",
                           "random:99999999999", "random:16777217"}) {
    EXPECT_THROW(make_preset(name), SceneError) << name;
  }
}

TEST(Presets, NamesListTheFour) {
  EXPECT_EQ(preset_names(),
            (std::vector<std::string>{"single", "three", "rtiow-final", "random:N"}));
  EXPECT_EQ(preset_descriptions().size(), preset_names().size());
}

TEST(SceneJson, ReadsTheIssuesExample) {
  Scene s = parse_scene(
      R"({"camera": {"lookfrom": [13,2,3], "lookat": [0,0,0], "vup": [0,1,0], "vfov": 20},
          "spheres": [{"center": [0,-1000,0], "radius": 1000, "color": [0.5,0.5,0.5]},
                      {"center": [1,2,3], "radius": 0.25}],
          "width": 320, "height": 200})",
      "example.json");
  ASSERT_EQ(s.spheres.size(), 2u);
  expect_sphere(s, 0, {0, -1000, 0}, 1000.0f);
  expect_sphere(s, 1, {1, 2, 3}, 0.25f);
  EXPECT_EQ(s.colors[0], (Vec3{0.5f, 0.5f, 0.5f}));
  EXPECT_EQ(s.colors[1], (Vec3{0.5f, 0.5f, 0.5f}));  // the documented default
  EXPECT_EQ(s.camera.lookfrom, (Vec3{13, 2, 3}));
  EXPECT_EQ(s.camera.vfov, 20.0f);
  EXPECT_EQ(s.width, 320);
  EXPECT_EQ(s.height, 200);
}

TEST(SceneJson, OneSideGivenKeepsSixteenByNine) {
  Scene s = parse_scene(R"({"width": 640, "spheres": []})", "w.json");
  EXPECT_EQ(s.height, 360);
}

std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "s.json");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(accepted)";
}

// Each bad document, and the message: the position is counted by hand (line:column, 1-based).
TEST(SceneJson, BadDocumentsSayWhereAndWhat) {
  EXPECT_EQ(error_of(""), "s.json: expected a JSON scene, the file is empty");
  EXPECT_EQ(error_of("[1]"), "s.json:1:1: expected the scene to be an object, got an array");
  EXPECT_EQ(error_of("{\n\"spheres\": [\n  {\"center\": [0,0,0], \"radius\": -1}]}"),
            "s.json:3:33: expected \"radius\" to be positive, got -1");
  EXPECT_EQ(
      error_of("{\"spheres\": [{\"center\": [0,0,0], \"radius\": 1, \"colour\": [1,1,1]}]}"),
      "s.json:1:47: expected one of the keys center, radius, color, material in a sphere, got "
      "unknown key \"colour\"");
  EXPECT_EQ(error_of("{\"spheres\": [{\"center\": [0,0,0]}]}"),
            "s.json:1:14: expected a sphere to have a \"radius\"");
  EXPECT_EQ(error_of("{\"spheres\": [{\"center\": [0,\"NaN\",0], \"radius\": 1}]}"),
            "s.json:1:28: expected \"center\" components to be a number, got a string");
  EXPECT_EQ(error_of("{\"spheres\": [{\"center\": [0,0], \"radius\": 1}]}"),
            "s.json:1:25: expected \"center\" to be an array of 3 numbers, got 2 elements");
  EXPECT_EQ(error_of("{\"spheres\": [{\"center\": [0,0,0], \"radius\": 1e39}]}"),
            "s.json:1:44: expected \"radius\" to be a finite number (as a float)");
  EXPECT_EQ(error_of("{\"spheres\": {}}"),
            "s.json:1:13: expected \"spheres\" to be an array, got an object");
  EXPECT_EQ(error_of("{}"), "s.json:1:1: expected the scene to have a \"spheres\" array");
  EXPECT_EQ(error_of("{\"camera\": {\"lookfrom\": [1,1,1], \"lookat\": [1,1,1]}, \"spheres\": []}"),
            "s.json:1:12: expected lookfrom and lookat to differ");
  EXPECT_EQ(error_of("{\"width\": 0, \"spheres\": []}"),
            "s.json:1:11: expected \"width\" to be an integer from 1 to 16384");
  EXPECT_EQ(error_of("{\"spheres\": [{\"center\": [0,0,0], \"radius\": 1, \"color\": [0,2,0]}]}"),
            "s.json:1:59: expected \"color\" components in [0, 1]");
}

// A sphere's material, and the defaults that let files without one load: Lambertian with the
// sphere's colour, the book's sky.
TEST(SceneJson, ReadsMaterialsAndTheSky) {
  Scene s = parse_scene(
      R"({"sky": {"horizon": [0.25, 0.5, 1], "zenith": [2, 2, 2]},
          "spheres": [{"center": [0,0,0], "radius": 1, "color": [0.1,0.2,0.3]},
                      {"center": [0,0,0], "radius": 1,
                       "material": {"type": "metal", "albedo": [0.7,0.6,0.5], "fuzz": 0.25}},
                      {"center": [0,0,0], "radius": 1, "material": {"type": "dielectric"}},
                      {"center": [0,0,0], "radius": 1,
                       "material": {"type": "dielectric", "ior": 2.4}},
                      {"center": [0,0,0], "radius": 1, "color": [0.9,0.8,0.7],
                       "material": {"type": "lambertian"}}]})",
      "m.json");
  ASSERT_EQ(s.materials.size(), 5u);
  EXPECT_EQ(s.materials[0].kind, MaterialKind::lambertian);
  EXPECT_EQ(s.materials[0].albedo, (Vec3{0.1f, 0.2f, 0.3f}));
  EXPECT_EQ(s.materials[1].kind, MaterialKind::metal);
  EXPECT_EQ(s.materials[1].albedo, (Vec3{0.7f, 0.6f, 0.5f}));
  EXPECT_EQ(s.materials[1].fuzz, 0.25f);
  EXPECT_EQ(s.colors[1], (Vec3{0.7f, 0.6f, 0.5f}));  // the other modes show the albedo
  EXPECT_EQ(s.materials[2].kind, MaterialKind::dielectric);
  EXPECT_EQ(s.materials[2].ior, 1.5f);  // the book's glass
  EXPECT_EQ(s.materials[3].ior, 2.4f);
  EXPECT_EQ(s.materials[4].albedo, (Vec3{0.9f, 0.8f, 0.7f}));
  EXPECT_EQ(s.sky.horizon, (Vec3{0.25f, 0.5f, 1}));
  EXPECT_EQ(s.sky.zenith, (Vec3{2, 2, 2}));
  Scene blurred = parse_scene(
      R"({"camera": {"defocus_angle": 2, "focus_dist": 3.5}, "spheres": []})", "b.json");
  EXPECT_EQ(blurred.camera.defocus_angle, 2.0f);
  EXPECT_EQ(blurred.camera.focus_dist, 3.5f);
  Scene plain = parse_scene(R"({"spheres": [{"center": [0,0,0], "radius": 1}]})", "p.json");
  EXPECT_EQ(plain.materials[0].kind, MaterialKind::lambertian);
  EXPECT_EQ(plain.materials[0].albedo, (Vec3{0.5f, 0.5f, 0.5f}));
  EXPECT_EQ(plain.sky.horizon, (Vec3{1, 1, 1}));
  EXPECT_EQ(plain.sky.zenith, (Vec3{0.5f, 0.7f, 1}));
  EXPECT_EQ(plain.camera.defocus_angle, 0.0f);  // a pinhole
  EXPECT_EQ(error_of(R"({"camera": {"focus_dist": 0}, "spheres": []})"),
            "s.json:1:12: expected a positive focus_dist, got 0.000000");
}

std::string material_error(const std::string& material) {
  return error_of(R"({"spheres": [{"center": [0,0,0], "radius": 1, "material": )" + material +
                  "}]}");
}

// Each bad material, and the message; the material starts at column 59 (counted by hand).
TEST(SceneJson, BadMaterialsSayWhereAndWhat) {
  EXPECT_EQ(material_error(R"({"type": "glass"})"),
            "s.json:1:68: expected \"type\" to be \"lambertian\", \"metal\" or \"dielectric\", "
            "got \"glass\"");
  EXPECT_EQ(material_error(R"({"albedo": [1,1,1]})"),
            "s.json:1:59: expected a material to have a \"type\"");
  EXPECT_EQ(material_error(R"({"type": "lambertian", "albedo": [0.5,1.5,0]})"),
            "s.json:1:97: expected \"albedo\" components in [0, 1]");
  EXPECT_EQ(material_error(R"({"type": "lambertian", "albedo": [0.5,-0.0001,0]})"),
            "s.json:1:97: expected \"albedo\" components in [0, 1]");
  EXPECT_EQ(material_error(R"({"type": "metal", "fuzz": -0.1})"),
            "s.json:1:85: expected \"fuzz\" in [0, 1], got -0.1");
  EXPECT_EQ(material_error(R"({"type": "dielectric", "ior": 0})"),
            "s.json:1:89: expected \"ior\" to be positive, got 0");
  EXPECT_EQ(material_error(R"({"type": "dielectric", "ior": -1.5})"),
            "s.json:1:89: expected \"ior\" to be positive, got -1.5");
  EXPECT_EQ(material_error(R"({"type": "dielectric", "ior": 1e39})"),
            "s.json:1:89: expected \"ior\" to be a finite number (as a float)");
  EXPECT_EQ(material_error(R"({"type": "dielectric", "albedo": [1,1,1]})"),
            "s.json:1:82: expected one of the keys type, ior in a dielectric material, got "
            "unknown key \"albedo\"");
  EXPECT_EQ(material_error(R"({"type": "metal", "shine": 1})"),
            "s.json:1:77: expected one of the keys type, albedo, fuzz, ior in a material, got "
            "unknown key \"shine\"");
  EXPECT_EQ(material_error(R"("metal")"),
            "s.json:1:59: expected a material to be an object, got a string");
  // JSON has no NaN: the parser refuses it, at its position.
  const std::string nan = material_error(R"({"type": "metal", "fuzz": NaN})");
  EXPECT_EQ(nan.rfind("s.json:1:85: expected valid JSON (", 0), 0u) << nan;
  EXPECT_EQ(error_of(R"({"sky": {"zenith": [1, -1, 1]}, "spheres": []})"),
            "s.json:1:24: expected \"zenith\" components >= 0");
  EXPECT_EQ(error_of(R"({"sky": {"sun": [1, 1, 1]}, "spheres": []})"),
            "s.json:1:10: expected one of the keys horizon, zenith in \"sky\", got unknown key "
            "\"sun\"");
}

TEST(SceneJson, SyntaxErrorsGiveTheParsersPosition) {
  std::string nan = error_of("{\"spheres\": [{\"center\": [0,NaN,0], \"radius\": 1}]}");
  EXPECT_EQ(nan.rfind("s.json:1:28: expected valid JSON (", 0), 0u) << nan;
  std::string trailing = error_of("{\"spheres\": []}\n{");
  EXPECT_EQ(trailing.rfind("s.json:2:1: expected valid JSON (", 0), 0u) << trailing;
  std::string open = error_of("{\n  \"spheres\": [\n");
  EXPECT_EQ(open.rfind("s.json:3:1: expected valid JSON (", 0), 0u) << open;
}

TEST(SceneJson, FilesThatCannotBeReadAreRefusedByName) {
  auto dir = std::filesystem::temp_directory_path() / "sphray-scene-test";
  std::filesystem::create_directories(dir);
  EXPECT_THROW(load_scene(dir / "missing.json"), SceneError);
  try {
    load_scene(dir);
    ADD_FAILURE() << "a directory was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), dir.string() + ": expected a scene file, got a directory");
  }
  std::filesystem::remove_all(dir);
}

TEST(SceneJson, TheExampleFilesLoad) {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(SPHRAY_SCENES_DIR)) {
    if (entry.path().extension() != ".json") continue;
    EXPECT_NO_THROW(load_scene(entry.path()).spheres.size()) << entry.path();
    ++files;
  }
  EXPECT_GE(files, 2);
}

TEST(SceneOrPreset, PicksByName) {
  EXPECT_EQ(load_scene_or_preset("three").spheres.size(), 3u);
  EXPECT_EQ(load_scene_or_preset("random:7").spheres.size(), 7u);
  EXPECT_THROW(load_scene_or_preset("no-such-scene"), SceneError);
  EXPECT_THROW(load_scene_or_preset("no-such-file.json"), SceneError);
}

}  // namespace
}  // namespace sphray::render
