// Regression tests for defects the fuzzers found (docs/robustness.md, "Defects found").
#include <gtest/gtest.h>

#include <string>

#include "sphray/render/scene.hpp"

namespace sphray::render {
namespace {

// Scene fuzzer: a number beyond double's range made nlohmann throw json::out_of_range (406)
// rather than parse_error, which escaped parse_scene and terminated the sphray command. It is
// a SceneError with the number's position like every other refusal.
TEST(Hardening, NumbersBeyondDoubleAreRefusedWithTheirPosition) {
  const struct {
    const char* text;
    const char* message;
  } cases[] = {
      {"{\n \"spheres\": [1e400]}",
       "x.json:2:14: expected a number within double's range (number overflow parsing '1e400')"},
      {R"({"spheres": [{"center": [0, -1e999, 0], "radius": 1}]})",
       "x.json:1:29: expected a number within double's range (number overflow parsing '-1e999')"},
  };
  for (const auto& c : cases) {
    try {
      parse_scene(c.text, "x.json");
      ADD_FAILURE() << "accepted " << c.text;
    } catch (const SceneError& e) {
      EXPECT_EQ(std::string(e.what()), c.message);
    }
  }
}

// Scene fuzzer: an unknown key with an escaped line break ("a\nb") was echoed raw, making the
// message two lines. Keys are quoted with JSON's escapes.
TEST(Hardening, UnknownKeysAreQuotedOnOneLine) {
  try {
    parse_scene(R"({"a\nb": true, "spheres": []})", "x.json");
    ADD_FAILURE() << "accepted an unknown key";
  } catch (const SceneError& e) {
    EXPECT_EQ(
        std::string(e.what()),
        "x.json:1:2: expected one of the keys name, camera, spheres, width, height, sky in the "
        "scene, got unknown key \"a\\nb\"");
  }
}

}  // namespace
}  // namespace sphray::render
