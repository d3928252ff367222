// The preset scenes. Each draws its randomness from SceneRandom with a fixed seed, so a preset
// is the same sphere for sphere on every run and every platform.
#include <charconv>
#include <cmath>
#include <numbers>
#include <string>

#include "sphray/particles/particles.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {
namespace {

constexpr std::uint32_t kRtiowSeed = 20160101u;
constexpr std::uint32_t kRandomSeed = 42u;

// A sphere whose colour (the other modes') stands for its material: the albedo, glass white.
void add_sphere(Scene& scene, Vec3 center, float radius, const Material& material) {
  scene.spheres.add(center, radius);
  bool glass = material.kind == MaterialKind::dielectric;
  scene.colors.push_back(glass ? Vec3{1, 1, 1} : material.albedo);
  scene.materials.push_back(material);
}

void add_sphere(Scene& scene, Vec3 center, float radius, Vec3 color) {
  add_sphere(scene, center, radius, Material{MaterialKind::lambertian, color});
}

Material metal(Vec3 albedo, float fuzz) {
  return {MaterialKind::metal, albedo, fuzz};
}

Material glass(float ior) {
  return {MaterialKind::dielectric, {1, 1, 1}, 0.0f, ior};
}

Vec3 random_color(SceneRandom& rng) {
  float r = rng.uniform();
  float g = rng.uniform();
  float b = rng.uniform();
  return {r, g, b};
}

// Ray Tracing in One Weekend, chapter 5: one sphere in front of a camera at the origin whose
// viewport is 2 high at focal length 1, which is a vertical field of view of 90 degrees.
Scene make_single() {
  Scene scene;
  scene.name = "single";
  add_sphere(scene, {0, 0, -1}, 0.5f, {1, 0, 0});
  scene.camera = CameraSpec{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90.0f};
  return scene;
}

Scene make_three() {
  Scene scene;
  scene.name = "three";
  add_sphere(scene, {0, 0, 0}, 1.0f, {0.9f, 0.15f, 0.1f});
  add_sphere(scene, {-2.2f, -0.3f, 0.5f}, 0.7f, {0.15f, 0.3f, 0.9f});
  add_sphere(scene, {2, -0.5f, 1}, 0.5f, {0.15f, 0.8f, 0.2f});
  // Slightly above, a little off-axis, with room around the outer spheres.
  scene.camera = CameraSpec{{0.5f, 1.5f, 7.0f}, {0, -0.2f, 0.3f}, {0, 1, 0}, 32.0f};
  return scene;
}

// Ray Tracing in One Weekend, chapter 14 ("Where Next?"): the cover scene, with the book's
// materials. The draws follow the book's order (material choice, then the centre, then the
// material's own draws: albedo = random() * random() for diffuse, albedo in [0.5, 1) and fuzz
// in [0, 0.5) for metal, glass of index 1.5), from a fixed seed.
Scene make_rtiow_final() {
  Scene scene;
  scene.name = "rtiow-final";
  SceneRandom rng(kRtiowSeed);
  scene.spheres.reserve(1 + 22 * 22 + 3);
  scene.colors.reserve(1 + 22 * 22 + 3);
  scene.materials.reserve(1 + 22 * 22 + 3);
  add_sphere(scene, {0, -1000, 0}, 1000.0f, {0.5f, 0.5f, 0.5f});
  for (int a = -11; a < 11; ++a) {
    for (int b = -11; b < 11; ++b) {
      float choose_material = rng.uniform();
      float cx = static_cast<float>(a) + 0.9f * rng.uniform();
      float cz = static_cast<float>(b) + 0.9f * rng.uniform();
      Vec3 center{cx, 0.2f, cz};
      if (length(center - Vec3{4, 0.2f, 0}) <= 0.9f) continue;
      if (choose_material < 0.8f) {
        add_sphere(scene, center, 0.2f, random_color(rng) * random_color(rng));
      } else if (choose_material < 0.95f) {
        float r = rng.uniform(0.5f, 1);
        float g = rng.uniform(0.5f, 1);
        float bl = rng.uniform(0.5f, 1);
        add_sphere(scene, center, 0.2f, metal({r, g, bl}, rng.uniform(0, 0.5f)));
      } else {
        add_sphere(scene, center, 0.2f, glass(1.5f));
      }
    }
  }
  add_sphere(scene, {0, 1, 0}, 1.0f, glass(1.5f));
  add_sphere(scene, {-4, 1, 0}, 1.0f, {0.4f, 0.2f, 0.1f});
  add_sphere(scene, {4, 1, 0}, 1.0f, metal({0.7f, 0.6f, 0.5f}, 0.0f));
  scene.camera = CameraSpec{{13, 2, 3}, {0, 0, 0}, {0, 1, 0}, 20.0f, 0.6f, 10.0f};
  scene.width = 1200;
  scene.height = 675;
  return scene;
}

// n spheres in the box [-50, 50]^3, radii in [0.5, 1.5] * 50 / cbrt(n) so the volume they
// fill stays about the same whatever n is, viewed from outside the box.
Scene make_random(std::size_t n) {
  Scene scene;
  scene.name = "random:" + std::to_string(n);
  SceneRandom rng(kRandomSeed);
  scene.spheres.reserve(n);
  scene.colors.reserve(n);
  scene.materials.reserve(n);
  float scale = 50.0f / std::cbrt(static_cast<float>(n));
  for (std::size_t i = 0; i < n; ++i) {
    float x = rng.uniform(-50, 50);
    float y = rng.uniform(-50, 50);
    float z = rng.uniform(-50, 50);
    float radius = rng.uniform(0.5f, 1.5f) * scale;
    add_sphere(scene, {x, y, z}, radius, random_color(rng));
  }
  // A sphere bounding the box and the largest radius fits the vertical field of view.
  scene.camera = framing({0, 0, 0}, 50.0f * std::numbers::sqrt3_v<float> + 1.5f * scale);
  return scene;
}

std::size_t parse_sphere_count(std::string_view text) {
  std::size_t n = 0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (error != std::errc{} || end != text.data() + text.size() || n == 0 || n > kMaxRandomSpheres) {
    throw SceneError("random:" + std::string(text) + ": expected random:N with N from 1 to " +
                     std::to_string(kMaxRandomSpheres));
  }
  return n;
}

}  // namespace

CameraSpec framing(Vec3 center, float bound) {
  float vfov = 40.0f;
  float distance = bound / std::sin(vfov / 2.0f * std::numbers::pi_v<float> / 180.0f);
  Vec3 from = center + normalize(Vec3{1.0f, 0.6f, 1.6f}) * distance;
  return CameraSpec{from, center, {0, 1, 0}, vfov};
}

std::vector<std::string> preset_names() {
  return {"single", "three", "rtiow-final", "random:N"};
}

std::vector<std::string> preset_descriptions() {
  return {
      "one sphere in front of the camera (Ray Tracing in One Weekend, chapter 5)",
      "three spheres, red, blue and green",
      "the cover of Ray Tracing in One Weekend: 486 spheres, fixed seed (the default)",
      "N spheres in a 100-unit box, fixed seed, N from 1 to " + std::to_string(kMaxRandomSpheres),
  };
}

Scene make_preset(std::string_view name) {
  if (name == "single") return make_single();
  if (name == "three") return make_three();
  if (name == "rtiow-final") return make_rtiow_final();
  constexpr std::string_view random_prefix = "random:";
  if (name.starts_with(random_prefix)) {
    return make_random(parse_sphere_count(name.substr(random_prefix.size())));
  }
  throw SceneError(std::string(name) +
                   ": expected a preset (single, three, rtiow-final, random:N) or a .json file");
}

std::vector<std::string> precision_names() {
  return {"float", "double"};
}

std::optional<Precision> parse_precision(std::string_view name) {
  if (name == "float") return Precision::float32;
  if (name == "double") return Precision::float64;
  return std::nullopt;
}

SceneDoubles doubles_of(const Scene& scene) {
  if (scene.doubles) return *scene.doubles;
  SceneDoubles doubles{
      {}, vec3_cast<double>(scene.camera.lookfrom), vec3_cast<double>(scene.camera.lookat)};
  const SphereSoA& spheres = scene.spheres;
  doubles.spheres.reserve(spheres.size());
  for (std::uint32_t id = 0; id < spheres.size(); ++id) {
    doubles.spheres.add(vec3_cast<double>(spheres.center(id)), spheres.radius(id),
                        spheres.mask(id));
  }
  return doubles;
}

namespace {

// A preset in the precision asked for: its floats, widened when double is asked.
Scene preset_in(std::string_view name, Precision precision) {
  Scene scene = make_preset(name);
  if (precision == Precision::float64) scene.doubles = doubles_of(scene);
  return scene;
}

}  // namespace

Scene load_scene_or_preset(std::string_view name_or_file, const SceneOptions& options) {
  bool is_preset_name = name_or_file == "single" || name_or_file == "three" ||
                        name_or_file == "rtiow-final" || name_or_file.starts_with("random:");
  std::filesystem::path file(name_or_file);
  const bool particle_file = !is_preset_name && particles::is_particle_file(file);
  // A preset or a scene file gives each sphere its material; one for all would silently
  // override them (docs/decisions.md, "A camera and materials on the command line").
  if (options.material && !particle_file)
    throw SceneError("--material applies to particle files (.xyz, .csv, .sphp), not to " +
                     std::string(name_or_file));
  if (is_preset_name) return preset_in(name_or_file, options.precision);
  if (name_or_file == "-") return load_scene(file, options.precision);  // standard input
  if (particle_file) return load_particle_scene(file, options);
  // The non-throwing exists(): a name too long, a symbolic link loop or a folder that cannot
  // be searched is an error of the file, which load_scene reports, not a missing file.
  std::error_code error;
  if (file.extension() != ".json" && !std::filesystem::exists(file, error) && !error) {
    return make_preset(name_or_file);  // neither a preset nor a file: the preset message
  }
  return load_scene(file, options.precision);
}

}  // namespace sphray::render
