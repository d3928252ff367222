// Scene parser fuzzer: any bytes given to parse_scene() give either a scene the renderer can use
// or a SceneError whose message is one line naming the source. Anything else (another
// exception, a crash, undefined behaviour, a leak, a hang) is a finding.
//
// An input whose first byte is '@' names a preset instead ("@random:12"), so make_preset's
// name parsing is fuzzed too; counts above 99999 are skipped only to keep each run short.
//
// An input "%N<rest>" stands for `{"spheres": ` followed by N '[' (N up to 200000) and <rest>:
// deep nesting in a few bytes. parse_scene refuses it at the nesting limit, so the error
// locator (json_position) is also run on it directly, under .ci/fuzz's RSS limit for this
// fuzzer (512 MB): a locator keeping a path string per level took 1.6 GB at 40,000 levels.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

#include "scene/json_position.hpp"
#include "sphray/render/camera.hpp"
#include "sphray/render/scene.hpp"

namespace {

using namespace sphray::render;

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "scene fuzzer: %s: %s\n", what, detail.c_str());
  std::abort();
}

bool in_unit(float c) {
  return c >= 0.0f && c <= 1.0f;
}

// What the renderer relies on in a scene that was accepted.
void check_scene(const Scene& scene) {
  const sphray::SphereView v = scene.spheres.view();
  if (scene.colors.size() != v.count) fail("colours and spheres differ in number", scene.name);
  for (std::size_t i = 0; i < v.count; ++i) {
    const sphray::Vec3 c{v.cx[i], v.cy[i], v.cz[i]};
    if (!sphray::isfinite(c) || !std::isfinite(v.radius[i]) || !(v.radius[i] > 0.0f))
      fail("accepted a sphere the kernel never hits", scene.name);
    const sphray::Vec3 k = scene.colors[i];
    if (!in_unit(k.x) || !in_unit(k.y) || !in_unit(k.z))
      fail("accepted a colour outside [0, 1]", scene.name);
  }
  if (scene.width < 1 || scene.height < 1 || scene.width > kMaxImageSide ||
      scene.height > kMaxImageSide)
    fail("accepted an image size out of range", scene.name);
  try {
    Camera camera(scene.camera, scene.width, scene.height);
  } catch (const SceneError& e) {
    fail("accepted a camera that cannot be placed", e.what());
  }
}

void check_error(const SceneError& e, std::string_view source) {
  const std::string message = e.what();
  // A name with a line break in it is echoed as given; the rest must fit on one line.
  if (source.find('\n') == std::string_view::npos && message.find('\n') != std::string::npos)
    fail("a message of more than one line", message);
  if (message.compare(0, source.size(), source) != 0)
    fail("a message not naming the source", message);
}

bool cheap_preset(std::string_view name) {
  if (name.substr(0, 7) != "random:") return true;
  std::size_t digits = 0;
  for (char ch : name.substr(7))
    digits += ch >= '0' && ch <= '9';
  return digits <= 5;
}

constexpr std::size_t kMaxDeep = 200000;

// "%N<rest>" expanded, or nothing if text is not of that form.
std::optional<std::string> expand_deep(std::string_view text) {
  if (text.empty() || text[0] != '%') return std::nullopt;
  std::size_t depth = 0, i = 1;
  for (; i < text.size() && i < 8 && text[i] >= '0' && text[i] <= '9'; ++i)
    depth = 10 * depth + static_cast<std::size_t>(text[i] - '0');
  if (i == 1 || depth > kMaxDeep) return std::nullopt;
  std::string expanded = "{\"spheres\": ";
  expanded.append(depth, '[');
  expanded.append(text.substr(i));
  return expanded;
}

// The locator's passes over any text: in bounds, and (by the RSS limit) small.
void locate_everything(std::string_view text) {
  namespace jp = sphray::render::json_position;
  const std::size_t at = jp::find_pointer(text, "/spheres/0/0/0", false);
  if (at > text.size()) fail("a position beyond the text", std::to_string(at));
  if (auto duplicate = jp::find_duplicate_key(text); duplicate && duplicate->offset > text.size())
    fail("a duplicate key beyond the text", duplicate->key);
  const std::size_t error = jp::first_error(text);
  if (error > text.size()) fail("an error beyond the text", std::to_string(error));
  (void)jp::line_column(text, error);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (!text.empty() && text[0] == '@') {
    const std::string_view name = text.substr(1);
    // A name comes from a command line: it has no NUL (what() would end there).
    if (!cheap_preset(name) || name.find('\0') != std::string_view::npos) return -1;
    try {
      check_scene(make_preset(name));
    } catch (const SceneError& e) {
      check_error(e, name);
    }
    return 0;
  }
  if (std::optional<std::string> deep = expand_deep(text)) {
    locate_everything(*deep);
    try {
      check_scene(parse_scene(*deep, "fuzz.json"));
    } catch (const SceneError& e) {
      check_error(e, "fuzz.json");
    }
    return 0;
  }
  try {
    check_scene(parse_scene(text, "fuzz.json"));
  } catch (const SceneError& e) {
    check_error(e, "fuzz.json");
  }
  return 0;
}
