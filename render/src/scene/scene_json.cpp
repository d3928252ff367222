// Scene files: JSON read with nlohmann_json, checked field by field, every refusal one line
// naming the file, the line and column, and what was expected there. Positions are found only
// when a check fails (json_position.hpp).
#include <cmath>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "scene/json_position.hpp"
#include "scene/scene_text.hpp"
#include "sphray/render/camera.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {
namespace {

using nlohmann::json;

// A check that failed: the path (a JSON pointer, keys unescaped: it is only matched, never
// resolved) of the value at fault, whether to point at its key
// rather than its value, and what was expected.
struct Invalid {
  std::string pointer;
  bool at_key;
  std::string expected;
};

[[noreturn]] void fail(const std::string& pointer, std::string expected, bool at_key = false) {
  throw Invalid{pointer, at_key, std::move(expected)};
}

std::string type_of(const json& value) {
  if (value.is_number()) return "a number";
  if (value.is_string()) return "a string";
  if (value.is_boolean()) return "a boolean";
  if (value.is_null()) return "null";
  if (value.is_array()) return "an array";
  return "an object";
}

float number_at(const json& value, const std::string& pointer, const std::string& what) {
  if (!value.is_number()) fail(pointer, what + " to be a number, got " + type_of(value));
  // Values beyond float's range become infinite here and are refused with the rest.
  float x = value.get<float>();
  if (!std::isfinite(x)) fail(pointer, what + " to be a finite number (as a float)");
  return x;
}

// The largest camera coordinate and sphere radius a scene may give: their squares (and the
// kernel's products of them) must stay far inside float's range, or every ray turns NaN (a
// lookfrom beyond about 1.8e19) or a sphere is never drawn (r^2 infinite).
constexpr float kMaxMagnitude = 1e17f;

std::string magnitude_limit() {
  return "at most 1e17 in magnitude (its square must fit a float)";
}

Vec3 vec3_at(const json& value, const std::string& pointer, const std::string& what) {
  if (!value.is_array() || value.size() != 3) {
    fail(pointer,
         what + " to be an array of 3 numbers, got " +
             (value.is_array() ? std::to_string(value.size()) + " elements" : type_of(value)));
  }
  Vec3 v{};
  float* out[3] = {&v.x, &v.y, &v.z};
  for (std::size_t i = 0; i < 3; ++i) {
    *out[i] = number_at(value[i], pointer + "/" + std::to_string(i), what + " components");
  }
  return v;
}

// A number vec3_at has accepted, as the double the file writes (Precision::float64).
Vec3d vec3_exact(const json& value) {
  return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
}

const json& object_at(const json& value, const std::string& pointer, const std::string& what,
                      std::initializer_list<std::string_view> allowed_keys) {
  if (!value.is_object()) fail(pointer, what + " to be an object, got " + type_of(value));
  for (const auto& [key, unused] : value.items()) {
    bool allowed = false;
    for (std::string_view k : allowed_keys)
      allowed = allowed || k == key;
    if (!allowed) {
      // The key is quoted with JSON's escapes (dump() of a parsed key cannot throw: the parser
      // checked its UTF-8), so a "\n" in it cannot break the one-line message.
      std::string list;
      for (std::string_view k : allowed_keys)
        list += (list.empty() ? "" : ", ") + std::string(k);
      fail(pointer + "/" + key,
           "one of the keys " + list + " in " + what + ", got unknown key " + json(key).dump(),
           true);
    }
  }
  return value;
}

int side_at(const json& value, const std::string& pointer, const std::string& what) {
  if (!value.is_number_integer() || value.get<std::int64_t>() < 1 ||
      value.get<std::int64_t>() > kMaxImageSide) {
    fail(pointer, what + " to be an integer from 1 to " + std::to_string(kMaxImageSide));
  }
  return value.get<int>();
}

// A camera vector whose components the camera may square and subtract in float.
Vec3 camera_vec3_at(const json& value, const std::string& pointer, const std::string& what) {
  Vec3 v = vec3_at(value, pointer, what);
  for (std::size_t i = 0; i < 3; ++i) {
    if (std::abs(v[static_cast<int>(i)]) > kMaxMagnitude)
      fail(pointer + "/" + std::to_string(i), what + " components " + magnitude_limit());
  }
  return v;
}

// In float, the camera must be placeable in float; in double, camera_doubles checks it.
CameraSpec camera_at(const json& value, Precision precision) {
  const json& camera =
      object_at(value, "/camera", "\"camera\"",
                {"lookfrom", "lookat", "vup", "vfov", "defocus_angle", "focus_dist"});
  CameraSpec spec;
  if (camera.contains("lookfrom"))
    spec.lookfrom = camera_vec3_at(camera["lookfrom"], "/camera/lookfrom", "\"lookfrom\"");
  if (camera.contains("lookat"))
    spec.lookat = camera_vec3_at(camera["lookat"], "/camera/lookat", "\"lookat\"");
  if (camera.contains("vup")) spec.vup = camera_vec3_at(camera["vup"], "/camera/vup", "\"vup\"");
  if (camera.contains("vfov")) spec.vfov = number_at(camera["vfov"], "/camera/vfov", "\"vfov\"");
  if (camera.contains("defocus_angle"))
    spec.defocus_angle =
        number_at(camera["defocus_angle"], "/camera/defocus_angle", "\"defocus_angle\"");
  if (camera.contains("focus_dist"))
    spec.focus_dist = number_at(camera["focus_dist"], "/camera/focus_dist", "\"focus_dist\"");
  try {
    if (precision == Precision::float32) {
      const Camera check(spec, 16, 9);
    }
  } catch (const SceneError& e) {
    std::string message = e.what();
    fail("/camera", message.substr(message.find("expected ") + 9));
  }
  return spec;
}

// An array of 3 numbers in [0, 1]: a colour or an albedo.
Vec3 unit_color_at(const json& value, const std::string& pointer, const std::string& what) {
  Vec3 color = vec3_at(value, pointer, what);
  for (int i = 0; i < 3; ++i) {
    if (!(color[i] >= 0.0f && color[i] <= 1.0f))
      fail(pointer + "/" + std::to_string(i), what + " components in [0, 1]");
  }
  return color;
}

// A sphere's "material" (docs/scenes.md): its "type" first, then the keys that type takes.
// albedo defaults to the sphere's colour, as a sphere without a material is that Lambertian.
Material material_at(const json& value, const std::string& pointer, Vec3 color) {
  const std::string what = "a material";
  object_at(value, pointer, what, {"type", "albedo", "fuzz", "ior"});
  if (!value.contains("type")) fail(pointer, "a material to have a \"type\"");
  const json& type = value["type"];
  std::optional<MaterialKind> kind;
  if (type.is_string()) kind = parse_material_kind(type.get<std::string>());
  if (!kind) {
    fail(pointer + "/type",
         "\"type\" to be \"lambertian\", \"metal\" or \"dielectric\", got " + type.dump());
  }
  Material m{*kind, color};
  switch (*kind) {
    case MaterialKind::lambertian:
      object_at(value, pointer, "a lambertian material", {"type", "albedo"});
      break;
    case MaterialKind::metal:
      object_at(value, pointer, "a metal material", {"type", "albedo", "fuzz"});
      break;
    case MaterialKind::dielectric:
      object_at(value, pointer, "a dielectric material", {"type", "ior"});
      m.albedo = {1, 1, 1};
      break;
  }
  if (value.contains("albedo"))
    m.albedo = unit_color_at(value["albedo"], pointer + "/albedo", "\"albedo\"");
  if (value.contains("fuzz")) {
    m.fuzz = number_at(value["fuzz"], pointer + "/fuzz", "\"fuzz\"");
    if (!(m.fuzz >= 0.0f && m.fuzz <= 1.0f))
      fail(pointer + "/fuzz", "\"fuzz\" in [0, 1], got " + value["fuzz"].dump());
  }
  if (value.contains("ior")) {
    m.ior = number_at(value["ior"], pointer + "/ior", "\"ior\"");
    if (!(m.ior > 0.0f))
      fail(pointer + "/ior", "\"ior\" to be positive, got " + value["ior"].dump());
  }
  return m;
}

// The sky that lights path mode: {"horizon": [r, g, b], "zenith": [r, g, b]}, radiances >= 0.
Sky sky_at(const json& value) {
  object_at(value, "/sky", "\"sky\"", {"horizon", "zenith"});
  Sky sky;
  Vec3* out[2] = {&sky.horizon, &sky.zenith};
  const char* keys[2] = {"horizon", "zenith"};
  for (int k = 0; k < 2; ++k) {
    if (!value.contains(keys[k])) continue;
    const std::string pointer = std::string("/sky/") + keys[k];
    const std::string what = std::string("\"") + keys[k] + "\"";
    *out[k] = vec3_at(value[keys[k]], pointer, what);
    for (int i = 0; i < 3; ++i) {
      if (!((*out[k])[i] >= 0.0f))
        fail(pointer + "/" + std::to_string(i), what + " components >= 0");
    }
  }
  return sky;
}

void check_radius(const json& value, float radius, const std::string& pointer) {
  if (radius == 0.0f && value.get<double>() > 0.0) {
    fail(pointer, "\"radius\" to be positive as a float, got " + value.dump() +
                      ", which underflows float to 0");
  }
  if (!(radius > 0.0f)) fail(pointer, "\"radius\" to be positive, got " + value.dump());
  if (radius > kMaxMagnitude) fail(pointer, "\"radius\" to be " + magnitude_limit());
}

void add_sphere_at(Scene& scene, const json& value, const std::string& pointer) {
  const json& sphere =
      object_at(value, pointer, "a sphere", {"center", "radius", "color", "material"});
  if (!sphere.contains("center")) fail(pointer, "a sphere to have a \"center\"");
  if (!sphere.contains("radius")) fail(pointer, "a sphere to have a \"radius\"");
  Vec3 center = vec3_at(sphere["center"], pointer + "/center", "\"center\"");
  float radius = number_at(sphere["radius"], pointer + "/radius", "\"radius\"");
  check_radius(sphere["radius"], radius, pointer + "/radius");
  Vec3 color{0.5f, 0.5f, 0.5f};
  if (sphere.contains("color")) {
    color = vec3_at(sphere["color"], pointer + "/color", "\"color\"");
    for (int i = 0; i < 3; ++i) {
      if (!(color[i] >= 0.0f && color[i] <= 1.0f)) {
        fail(pointer + "/color/" + std::to_string(i), "\"color\" components in [0, 1]");
      }
    }
  }
  Material material{MaterialKind::lambertian, color};
  if (sphere.contains("material")) {
    material = material_at(sphere["material"], pointer + "/material", color);
    if (!sphere.contains("color")) color = material.albedo;  // the other modes show the albedo
  }
  scene.spheres.add(center, radius);
  if (scene.doubles)
    scene.doubles->spheres.add(vec3_exact(sphere["center"]), sphere["radius"].get<double>());
  scene.colors.push_back(color);
  scene.materials.push_back(material);
}

// The image size: both given, or one given and the other following 16:9, or the default.
void size_at(Scene& scene, const json& root) {
  bool has_width = root.contains("width"), has_height = root.contains("height");
  if (has_width) scene.width = side_at(root["width"], "/width", "\"width\"");
  if (has_height) scene.height = side_at(root["height"], "/height", "\"height\"");
  if (has_width && !has_height) scene.height = std::max(1, scene.width * 9 / 16);
  if (has_height && !has_width) scene.width = std::min(kMaxImageSide, scene.height * 16 / 9);
}

// The camera's position and target as written, checked as a camera in double: a camera a few
// millimetres from what it looks at, kilometres from the origin, may round to one point in float.
SceneDoubles camera_doubles(const json& root, const CameraSpec& spec) {
  SceneDoubles doubles{{}, vec3_cast<double>(spec.lookfrom), vec3_cast<double>(spec.lookat)};
  if (!root.contains("camera")) return doubles;
  const json& camera = root["camera"];
  if (camera.contains("lookfrom")) doubles.lookfrom = vec3_exact(camera["lookfrom"]);
  if (camera.contains("lookat")) doubles.lookat = vec3_exact(camera["lookat"]);
  try {
    Camerad check(spec, doubles.lookfrom, doubles.lookat, 16, 9);
  } catch (const SceneError& e) {
    std::string message = e.what();
    fail("/camera", message.substr(message.find("expected ") + 9));
  }
  return doubles;
}

Scene scene_from(const json& root, const std::string& source, Precision precision) {
  object_at(root, "", "the scene", {"name", "camera", "spheres", "width", "height", "sky"});
  Scene scene;
  scene.name = source;
  if (root.contains("name")) {
    if (!root["name"].is_string()) fail("/name", "\"name\" to be a string");
    scene.name = root["name"].get<std::string>();
  }
  if (root.contains("camera")) scene.camera = camera_at(root["camera"], precision);
  if (precision == Precision::float64) scene.doubles = camera_doubles(root, scene.camera);
  if (root.contains("sky")) scene.sky = sky_at(root["sky"]);
  size_at(scene, root);
  if (!root.contains("spheres")) fail("", "the scene to have a \"spheres\" array");
  const json& spheres = root["spheres"];
  if (!spheres.is_array()) fail("/spheres", "\"spheres\" to be an array, got " + type_of(spheres));
  scene.spheres.reserve(spheres.size());
  if (scene.doubles) scene.doubles->spheres.reserve(spheres.size());
  scene.colors.reserve(spheres.size());
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    add_sphere_at(scene, spheres[i], "/spheres/" + std::to_string(i));
  }
  return scene;
}

std::string locate(std::string_view text, const Invalid& invalid) {
  return json_position::line_column(
      text, json_position::find_pointer(text, invalid.pointer, invalid.at_key));
}

// nlohmann's parse_error reads "[json.exception.parse_error.101] parse error at line 2,
// column 5: syntax error while parsing ..."; keep what follows the position.
std::string parse_error_detail(const json::parse_error& e) {
  std::string message = e.what();
  std::size_t column = message.find("column ");
  std::size_t colon = message.find(": ", column == std::string::npos ? 0 : column);
  return colon == std::string::npos ? message : message.substr(colon + 2);
}

}  // namespace

namespace {

// text as JSON, with the scene files' limits (nesting, numbers, repeated keys); what names the
// expected document in the message for empty text. Throws SceneError.
json parse_checked(std::string_view text, const std::string& source, const std::string& what) {
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    throw SceneError(source + ": expected " + what + ", the file is empty");
  }
  // The format nests four levels (the scene, "spheres", a sphere, its "center"); a limit far
  // above that keeps what nlohmann builds for a hostile file (about 100 bytes per level) small.
  if (auto deep = json_position::find_nesting_beyond(text, kMaxSceneNesting)) {
    throw SceneError(source + ":" + json_position::line_column(text, *deep) +
                     ": expected at most " + std::to_string(kMaxSceneNesting) +
                     " levels of nested arrays and objects");
  }
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    // e.byte counts the characters read, the offending one included.
    std::size_t offset = e.byte > 0 ? e.byte - 1 : 0;
    throw SceneError(source + ":" + json_position::line_column(text, offset) +
                     ": expected valid JSON (" + parse_error_detail(e) + ")");
  } catch (const json::out_of_range& e) {
    const std::string message = e.what();  // "[json.exception.out_of_range.406] number ..."
    throw SceneError(source + ":" +
                     json_position::line_column(text, json_position::first_error(text)) +
                     ": expected a number within double's range (" +
                     message.substr(message.find("] ") + 2) + ")");
  }
  // nlohmann keeps the last of repeated keys; a scene file that names a field twice is refused
  // rather than read in a way its author may not have meant.
  if (auto duplicate = json_position::find_duplicate_key(text)) {
    throw SceneError(source + ":" + json_position::line_column(text, duplicate->offset) +
                     ": expected each key once in an object, got " + json(duplicate->key).dump() +
                     " again");
  }
  return root;
}

}  // namespace

Scene parse_scene(std::string_view text, const std::string& source, Precision precision) {
  const json root = parse_checked(text, source, "a JSON scene");
  try {
    return scene_from(root, source, precision);
  } catch (const Invalid& invalid) {
    throw SceneError(source + ":" + locate(text, invalid) + ": expected " + invalid.expected);
  }
}

MaterialEntry parse_material(std::string_view text, const std::string& source) {
  const json root = parse_checked(text, source, "a JSON material");
  try {
    MaterialEntry entry{material_at(root, "", Vec3{0.5f, 0.5f, 0.5f}), root.contains("albedo")};
    entry.albedo_given |= entry.material.kind == MaterialKind::dielectric;
    return entry;
  } catch (const Invalid& invalid) {
    throw SceneError(source + ":" + locate(text, invalid) + ": expected " + invalid.expected);
  }
}

Scene load_scene(const std::filesystem::path& file, Precision precision) {
  if (file == kStandardInputName)
    return parse_scene(read_scene_stdin(), std::string(kStandardInputSource), precision);
  return parse_scene(read_scene_file(file), file.string(), precision);
}

}  // namespace sphray::render
