// Issue 20, scene files: values a float cannot carry, duplicate keys, columns after a byte
// order mark, the nesting limit, the size cap, standard input, and the error locator's memory.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "scene/json_position.hpp"
#include "scene/scene_text.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {
namespace {

std::string refusal(const std::string& text) {
  try {
    parse_scene(text, "x.json");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(SceneLimits, LookfromWhoseSquareOverflowsIsRefusedWithItsPosition) {
  // 2e19 squared is 4e38, beyond FLT_MAX (3.4e38): every ray would be NaN, an all-black image.
  EXPECT_EQ(refusal(R"({"camera": {"lookfrom": [2e19, 0, 0]}, "spheres": []})"),
            "x.json:1:26: expected \"lookfrom\" components at most 1e17 in magnitude (its square "
            "must fit a float)");
}

TEST(SceneLimits, RadiusWhoseSquareOverflowsIsRefusedWithItsPosition) {
  EXPECT_EQ(refusal(R"({"spheres": [{"center": [0, 0, -1], "radius": 2e19}]})"),
            "x.json:1:47: expected \"radius\" to be at most 1e17 in magnitude (its square must "
            "fit a float)");
}

TEST(SceneLimits, RadiusThatUnderflowsFloatIsNamedSo) {
  EXPECT_EQ(refusal(R"({"spheres": [{"center": [0, 0, -1], "radius": 1e-50}]})"),
            "x.json:1:47: expected \"radius\" to be positive as a float, got 1e-50, which "
            "underflows float to 0");
}

TEST(SceneLimits, DuplicateKeysAreRefusedAtTheSecondCopy) {
  EXPECT_EQ(refusal("{\"spheres\": [],\n \"spheres\": [1]}"),
            "x.json:2:2: expected each key once in an object, got \"spheres\" again");
  // An error inside the second copy was reported at the first: now the copy itself is named.
  EXPECT_EQ(refusal(R"({"spheres": [{"center": [0, 0, -1], "radius": 1, "radius": -1}]})"),
            "x.json:1:50: expected each key once in an object, got \"radius\" again");
}

TEST(SceneLimits, ColumnsCountCharactersNotBytes) {
  // The byte order mark (3 bytes) and "é" (2 bytes) are one character each, the BOM not shown.
  EXPECT_EQ(
      refusal("\xEF\xBB\xBF{\"spheres\": [], \"x\": 1}"),
      "x.json:1:17: expected one of the keys name, camera, spheres, width, height, sky in the "
      "scene, got unknown key \"x\"");
  EXPECT_EQ(
      refusal("{\"name\": \"\xC3\xA9\", \"x\": 1}"),
      "x.json:1:15: expected one of the keys name, camera, spheres, width, height, sky in the "
      "scene, got unknown key \"x\"");
}

TEST(SceneLimits, NestingBeyondTheLimitIsRefusedWhereItStarts) {
  std::string deep = "{\"spheres\": " + std::string(kMaxSceneNesting, '[');
  EXPECT_EQ(refusal(deep), "x.json:1:" + std::to_string(13 + kMaxSceneNesting - 1) +
                               ": expected at most 64 levels of nested arrays and objects");
  // Brackets inside strings are not nesting.
  EXPECT_EQ(refusal("{\"name\": \"" + std::string(1000, '[') + "\", \"spheres\": []}"), "accepted");
}

// The locator (json_position) on 100,000 levels, below the nesting check, in a child process
// whose peak memory is read back: it keeps one path string (linear), where one string per level
// (the old locator: 1.6 GB at 40,000 levels) took 9.8 GB here.
TEST(SceneLimits, ErrorLocatorMemoryIsLinearInTheNesting) {
  constexpr std::size_t kDepth = 100000;
  std::string text =
      "{\"spheres\": " + std::string(kDepth, '[') + std::string(kDepth, ']') + ", \"spheres\": 1}";
  rusage before{};
  ::getrusage(RUSAGE_CHILDREN, &before);
  pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    auto duplicate = json_position::find_duplicate_key(text);
    std::size_t at = json_position::find_pointer(text, "/spheres/0/0/0/0", false);
    std::_Exit(duplicate && duplicate->key == "spheres" && at == 16 ? 0 : 3);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "the locator found the wrong places";
  rusage after{};
  ::getrusage(RUSAGE_CHILDREN, &after);
  // ru_maxrss in KiB: the child starts as a copy of this process, so its own size is included.
  rusage self{};
  ::getrusage(RUSAGE_SELF, &self);
  EXPECT_LT(after.ru_maxrss - self.ru_maxrss, 64 * 1024)
      << "the child peaked at " << after.ru_maxrss << " KiB, this process at " << self.ru_maxrss;
}

TEST(SceneLimits, DevZeroIsCutAtTheSizeCap) {
  try {
    read_scene_file("/dev/zero");
    ADD_FAILURE() << "read /dev/zero to its end";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()),
              "/dev/zero: expected a scene file of at most 64 MiB, got more");
  }
}

TEST(SceneLimits, FileOverTheSizeCapIsRefusedBeforeReading) {
  // A sparse file of 64 MiB and one byte: refused by its size, without reading it.
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "sphray-scene-limits-large.json";
  { std::ofstream(file) << "{}"; }
  std::filesystem::resize_file(file, kMaxSceneBytes + 1);
  try {
    load_scene(file);
    ADD_FAILURE() << "accepted a file over the cap";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()),
              file.string() + ": expected a scene file of at most 64 MiB, got more");
  }
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace sphray::render
