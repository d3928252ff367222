// Scenes: the presets (single, three, rtiow-final, random:N) and JSON scene files.
//
// Every generator is deterministic: it draws from std::mt19937 (whose output the standard
// fixes) through hand-written conversions to float, never through std::uniform_*_distribution
// (whose output differs between standard libraries), so a preset is the same on every platform.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "sphray/render/material.hpp"
#include "sphray/sphray.hpp"

namespace sphray::render {

/// A pinhole camera as Ray Tracing in One Weekend places it.
struct CameraSpec {
  Vec3 lookfrom{0, 0, 0};
  Vec3 lookat{0, 0, -1};
  Vec3 vup{0, 1, 0};
  float vfov = 90.0f;  // vertical field of view, degrees
  /// Path mode's depth of field, the book's defocus blur: the angle (degrees) of the cone from
  /// each pixel's point on the plane in focus to the lens; 0 is a pinhole. The other modes
  /// always use the pinhole.
  float defocus_angle = 0.0f;
  float focus_dist = 10.0f;  // from lookfrom to the plane in focus, along the view direction
};

/// The precision a scene is traced in (`sphray render --precision`).
enum class Precision { float32, float64 };

/// "float", "double", in that order.
std::vector<std::string> precision_names();
std::optional<Precision> parse_precision(std::string_view name);

/// A scene's geometry in double, for Precision::float64 (docs/double.md, "The command"): its
/// spheres and its camera's position and target as written. A scene file's numbers and a text
/// or PLY particle file's fields are read again as doubles; what a preset or a binary file
/// holds as floats is widened, exactly.
struct SceneDoubles {
  SphereSoAd spheres;
  Vec3d lookfrom, lookat;
};

struct Scene {
  std::string name;
  SphereSoA spheres;
  /// One per sphere, each component in [0,1], or none: every sphere grey (color_of). A particle
  /// file without colours leaves it empty, which spares 12 bytes a sphere.
  std::vector<Vec3> colors;
  /// One per sphere for path mode, or none: every sphere is then default_material with its
  /// colour as albedo (material_of), as a scene built by hand or a particle file is.
  std::vector<Material> materials;
  /// The material of a sphere without an entry in materials: its kind, fuzz and ior (the albedo
  /// is the sphere's colour). Lambertian unless `--material` says otherwise for a particle file.
  Material default_material;
  Sky sky;  // what lights path mode
  CameraSpec camera;
  int width = 400, height = 225;  // default image size
  /// Loaded with Precision::float64: the same geometry in double (spheres and camera above
  /// hold it rounded to float). Empty otherwise.
  std::optional<SceneDoubles> doubles;
};

/// scene.doubles, or, for a scene loaded in float, its spheres and camera widened to double.
SceneDoubles doubles_of(const Scene& scene);

/// The grey of a sphere without a colour (scene files' default).
inline constexpr Vec3 kDefaultColor{0.5f, 0.5f, 0.5f};

/// Sphere id's colour: scene.colors[id], or grey without one.
inline Vec3 color_of(const Scene& scene, std::uint32_t id) {
  return id < scene.colors.size() ? scene.colors[id] : kDefaultColor;
}

/// Sphere id's material: scene.materials[id], or the default material (Lambertian unless said
/// otherwise) with its colour as albedo.
inline Material material_of(const Scene& scene, std::uint32_t id) {
  if (id < scene.materials.size()) return scene.materials[id];
  Material m = scene.default_material;
  m.albedo = color_of(scene, id);
  return m;
}

/// A scene that cannot be made: an unknown preset, or a file that is missing, unreadable,
/// malformed or invalid. what() is one line, "file:line:col: expected ..." when the position
/// is known, "file: ..." otherwise.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The largest N random:N accepts, and the largest width or height a scene may ask for.
inline constexpr std::size_t kMaxRandomSpheres = std::size_t{1} << 24;
inline constexpr int kMaxImageSide = 16384;

/// The deepest nesting of arrays and objects a scene file may have (the format uses four).
inline constexpr std::size_t kMaxSceneNesting = 64;

/// "single", "three", "rtiow-final", "random:N".
std::vector<std::string> preset_names();
/// One line describing each preset, in the order of preset_names().
std::vector<std::string> preset_descriptions();
/// The preset called name. Throws SceneError for an unknown name or a bad N.
Scene make_preset(std::string_view name);
/// A scene read from a JSON file (format in docs/scenes.md), or from standard input if file is
/// "-" (name a file called "-" as "./-"). A file may hold at most 64 MiB; a FIFO that gives no
/// byte within 5 s is refused. Throws SceneError.
/// Precision::float64 also keeps its numbers in double (Scene::doubles).
Scene load_scene(const std::filesystem::path& file, Precision precision = Precision::float32);
/// A scene parsed from JSON text; source names it in messages. Throws SceneError.
Scene parse_scene(std::string_view json_text, const std::string& source,
                  Precision precision = Precision::float32);
/// A sphere's "material" as scene files write it (docs/scenes.md), parsed from JSON text with
/// the same checks; source names it in messages. albedo_given: whether the material fixes its
/// albedo (an "albedo" key, or a dielectric); otherwise the sphere's colour is its albedo
/// (material.albedo holds the default grey). Throws SceneError.
struct MaterialEntry {
  Material material;
  bool albedo_given = false;
};
MaterialEntry parse_material(std::string_view json_text, const std::string& source);
/// What a particle file may leave to the caller.
struct SceneOptions {
  /// The radius of every particle of a text or PLY file without a radius (`--radius`).
  std::optional<float> radius;
  /// Every particle's material (`--material`), its albedo the particle's colour; Lambertian
  /// without. Only for particle files: load_scene_or_preset refuses it for other scenes.
  std::optional<Material> material;
  /// Precision::float64 also keeps the geometry in double (Scene::doubles).
  Precision precision = Precision::float32;
};
/// A preset if name_or_file names one (or starts with "random:"), a particle file if its
/// extension is .sphp, .xyz, .csv or .ply (load_particle_scene), else a JSON file ("-":
/// standard input).
Scene load_scene_or_preset(std::string_view name_or_file, const SceneOptions& options = {});
/// The spheres of a particle file (sphray/particles/particles.hpp), their colours from the file
/// (none stored without: every sphere grey), options.material (Lambertian without), framed by
/// framing(). Throws SceneError with the reader's message (or for an empty .sphp file).
Scene load_particle_scene(const std::filesystem::path& file, const SceneOptions& options = {});
/// The camera of random:N and of particle files: outside the ball of centre center and radius
/// bound, looking at its centre from direction (1, 0.6, 1.6), vfov 40, the whole ball in view.
CameraSpec framing(Vec3 center, float bound);

/// The fixed, portable random numbers every preset draws from.
class SceneRandom {
 public:
  explicit SceneRandom(std::uint32_t seed) : engine_(seed) {}
  /// Uniform in [0, 1): the top 24 bits of one mt19937 output, exact in float.
  float uniform() { return static_cast<float>(engine_() >> 8) * 0x1p-24f; }
  /// Uniform in [lo, hi).
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }

 private:
  std::mt19937 engine_;
};

}  // namespace sphray::render
