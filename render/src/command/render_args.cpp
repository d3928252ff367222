#include "command/render_args.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "sphray/render/camera.hpp"
#include "sphray/render/image_file.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {

CLI::Validator seed_range() {
  const std::string range = "0 to " + std::to_string(std::numeric_limits<std::uint64_t>::max());
  return CLI::Validator(
      [range](std::string& text) -> std::string {
        std::uint64_t value = 0;
        const char* end = text.data() + text.size();
        auto [stop, error] = std::from_chars(text.data(), end, value);
        const bool digits_only = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
          return c >= '0' && c <= '9';
        });
        if (digits_only && error == std::errc() && stop == end) return "";
        return "Value " + text + " not in range " + range;
      },
      "UINT64", "seed range");
}

CLI::Validator seconds_validator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double seconds = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !(seconds >= 0.0 && seconds <= 1e9))
          return "expected seconds from 0 to 1e9, got " + text;
        return {};
      },
      "SECONDS");
}

namespace {

// A number as C writes it, finite as a float; nothing else (no blanks, no trailing text).
std::optional<float> finite_float(const std::string& text) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return std::nullopt;
  char* end = nullptr;
  const float value = std::strtof(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

// "X,Y,Z": three finite numbers, each at most 1e17 in magnitude as a scene file's camera
// coordinates must be (their squares must fit a float). Read as doubles, as a scene file's are:
// a scene traced in double keeps them.
std::optional<Vec3d> parse_vec3(const std::string& text) {
  double parts[3];
  std::size_t start = 0;
  for (int i = 0; i < 3; ++i) {
    const std::size_t comma = i < 2 ? text.find(',', start) : text.size();
    if (comma == std::string::npos) return std::nullopt;
    const std::string part = text.substr(start, comma - start);
    if (part.empty() || std::isspace(static_cast<unsigned char>(part[0]))) return std::nullopt;
    char* end = nullptr;
    const double value = std::strtod(part.c_str(), &end);
    if (end != part.c_str() + part.size() || !(std::abs(value) <= 1e17)) return std::nullopt;
    parts[i] = value;
    start = comma + 1;
  }
  return Vec3d{parts[0], parts[1], parts[2]};
}

CLI::Validator vec3_validator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (parse_vec3(text)) return {};
        return "expected X,Y,Z: three finite numbers of at most 1e17 in magnitude, got " + text;
      },
      "");
}

// CLI::Range lets NaN through; a field of view of 0 or 180 degrees has no image.
CLI::Validator vfov_validator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const std::optional<float> vfov = finite_float(text);
        if (vfov && *vfov > 0.0f && *vfov < 180.0f) return {};
        return "expected degrees in (0, 180), got " + text;
      },
      "");
}

CLI::Validator material_validator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        try {
          parse_material_option(text);
          return {};
        } catch (const SceneError& e) {
          return e.what();
        }
      },
      "");
}

// What a check expected, without the prefix naming what was checked ("camera: ",
// "--material:1:20: "): the caller names the options instead.
std::string expected_part(const SceneError& e) {
  const std::string message = e.what();
  const std::size_t expected = message.find("expected ");
  return expected == std::string::npos ? message : message.substr(expected);
}

}  // namespace

Material parse_material_option(std::string_view text) {
  const std::size_t colon = text.find(':');
  const std::string name(text.substr(0, colon));
  const std::string number =
      colon == std::string_view::npos ? "" : std::string(text.substr(colon + 1));
  const bool metal = name == "metal", glass = name == "glass" || name == "dielectric";
  const std::optional<float> value = finite_float(number);
  const bool bare = colon == std::string_view::npos;
  if (!((name == "lambertian" && bare) || ((metal || glass) && (bare || value)))) {
    throw SceneError("expected lambertian, metal[:FUZZ] or glass[:IOR], got " + std::string(text));
  }
  // The scene files' parser checks and fills in the rest, so both spell the same materials.
  std::string json = "{\"type\": \"" + std::string(glass ? "dielectric" : name) + "\"";
  if (value) {
    char digits[32];
    std::snprintf(digits, sizeof digits, "%.9g", static_cast<double>(*value));
    json += std::string(metal ? ", \"fuzz\": " : ", \"ior\": ") + digits;
  }
  try {
    return parse_material(json + "}", "--material").material;
  } catch (const SceneError& e) {
    throw SceneError(expected_part(e));  // "expected \"fuzz\" in [0, 1], got 2"
  }
}

void add_camera_options(CLI::App& command, CameraArgs& camera) {
  const auto add = [&command](const char* name, const char* help, auto on_parse) {
    command
        .add_option_function<std::string>(
            name, [on_parse](const std::string& text) { on_parse(*parse_vec3(text)); }, help)
        ->check(vec3_validator())
        ->type_name("X,Y,Z");
  };
  add("--lookfrom", "Where the camera is (default: the scene's)",
      [&camera](Vec3d v) { camera.lookfrom = v; });
  add("--lookat", "The point at the image centre (default: the scene's)",
      [&camera](Vec3d v) { camera.lookat = v; });
  add("--vup", "Which way is up (default: the scene's)",
      [&camera](Vec3d v) { camera.vup = vec3_cast<float>(v); });
  command.add_option("--vfov", camera.vfov, "Vertical field of view (default: the scene's)")
      ->check(vfov_validator())
      ->type_name("DEG");
}

void apply_camera(const CameraArgs& camera, Scene& scene) {
  CameraSpec spec = scene.camera;
  std::optional<SceneDoubles> doubles = scene.doubles;
  std::string given;
  auto take = [&given](const char* name, auto& part, const auto& value) {
    if (!value) return;
    part = *value;
    given += (given.empty() ? "" : ", ") + std::string(name);
  };
  const auto narrowed = [](const std::optional<Vec3d>& v) {
    return v ? std::optional(vec3_cast<float>(*v)) : std::nullopt;
  };
  take("--lookfrom", spec.lookfrom, narrowed(camera.lookfrom));
  take("--lookat", spec.lookat, narrowed(camera.lookat));
  take("--vup", spec.vup, camera.vup);
  take("--vfov", spec.vfov, camera.vfov);
  if (given.empty()) return;
  if (doubles) {
    doubles->lookfrom = camera.lookfrom.value_or(doubles->lookfrom);
    doubles->lookat = camera.lookat.value_or(doubles->lookat);
  }
  try {
    // The camera is checked in the precision it is traced in.
    if (doubles) {
      const Camerad check(spec, doubles->lookfrom, doubles->lookat, 16, 9);
    } else {
      const Camera check(spec, 16, 9);
    }
  } catch (const SceneError& e) {
    throw SceneError(given + " with the camera of " + scene.name + ": " + expected_part(e));
  }
  scene.camera = spec;
  scene.doubles = std::move(doubles);
}

SceneOptions scene_options(const RenderArgs& args) {
  return {args.radius, args.material,
          args.precision == "double" ? Precision::float64 : Precision::float32};
}

void add_render_options(CLI::App& render, RenderArgs& args, RenderArgsScope scope) {
  render
      .add_option("--scene,-s", args.scene,
                  "A preset (see `sphray scenes`), a .json file or a particle file (.sphp, .xyz, "
                  ".csv, .ply)")
      ->capture_default_str();
  render
      .add_option("--radius", args.radius,
                  "The radius of every particle of a .xyz, .csv or .ply file without a radius")
      ->check(CLI::Range(0x1p-126, 1e17))
      ->type_name("R");
  render
      .add_option_function<std::string>(
          "--material",
          [&args](const std::string& text) { args.material = parse_material_option(text); },
          "Every particle's material, its albedo the particle's colour: lambertian (default), "
          "metal[:FUZZ] or glass[:IOR]; particle files only")
      ->check(material_validator())
      ->type_name("KIND");
  render.add_option("--mode,-m", args.mode, "What to show")
      ->check(CLI::IsMember(mode_names()))
      ->capture_default_str();
  render.add_option("--width,-W", args.width, "Image width (default: the scene's)")
      ->check(CLI::Range(1, kMaxImageSide));
  render.add_option("--height,-H", args.height, "Image height (default: the scene's)")
      ->check(CLI::Range(1, kMaxImageSide));
  render.add_option("--spp", args.spp, "Samples per pixel (1: pixel centres, more: jittered)")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  if (scope.threads) {
    render.add_option("--threads,-j", args.threads, "Worker threads (0: all cores)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
  }
  render.add_option("--seed", args.seed, "Seed of the sample jitter (0 to 2^64 - 1)")
      ->check(seed_range())
      ->capture_default_str();
  render.add_option("--max-depth", args.max_depth, "Path mode: rays per path at most")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  if (scope.time_limit) {
    render
        .add_option("--time-limit", args.time_limit,
                    "Path mode: seconds after which no sample is started (0: none); every pixel "
                    "gets the same samples, at least one")
        ->check(seconds_validator())
        ->capture_default_str();
  }
  add_camera_options(render, args.camera);
  render.add_option("-o,--output", args.output, "Output image, .png or .ppm")
      ->capture_default_str();
  if (scope.accel) {
    render
        .add_option("--accel", args.accel,
                    "Sphere queries: a BVH from 128 spheres on (auto), always, or brute force")
        ->check(CLI::IsMember(accel_names()))
        ->capture_default_str();
  }
  if (scope.precision) {
    render
        .add_option("--precision", args.precision,
                    "Trace the geometry in float or in double (a scene far from the origin "
                    "or finer than float's spacing there; not path mode)")
        ->check(CLI::IsMember(precision_names()))
        ->capture_default_str();
  }
  render.add_flag("--quiet,-q", args.quiet, "No progress bar, no summary line");
  if (scope.force)
    render.add_flag("--force,-f", args.force, "Replace the output even if it is read-only");
}

}  // namespace sphray::render
