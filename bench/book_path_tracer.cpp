// sphray_book_path: the baseline of issue 33, a path tracer written the way Ray Tracing in One
// Weekend (v4) writes one: double precision, a hittable base class whose virtual hit() a list
// calls for every sphere, one ray at a time, a recursive ray_color, materials with a virtual
// scatter, the book's random numbers (one std::mt19937_64 through uniform_real_distribution).
//
// It renders what `sphray render -m path` renders, by the same rules: the book's camera (with its
// defocus blur), each sample jittered in its pixel, the scene's materials and sky, at most
// --max-depth rays per path (the camera ray included; a path still going after them brings no
// light), the mean of --spp samples, gamma 2, bytes as int(255.999 c). The two images agree in
// expectation and differ in noise (tests/render/book_path_test.cpp checks it). It runs on one
// thread and prints its rays and their rate over the tracing alone as sphray's summary line
// does, for bench/path_vs_book.py.
//
// From sphray it takes only the scene (presets and files, through the same loader) and the image
// writer: everything traced and shaded is this file's own code.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "sphray/render/image_file.hpp"
#include "sphray/render/scene.hpp"

namespace {

// ---- vec3, ray: the book's chapters 3 and 4, in double ----

class vec3 {
 public:
  double e[3];

  vec3() : e{0, 0, 0} {}
  vec3(double e0, double e1, double e2) : e{e0, e1, e2} {}

  double x() const { return e[0]; }
  double y() const { return e[1]; }
  double z() const { return e[2]; }

  vec3 operator-() const { return vec3(-e[0], -e[1], -e[2]); }
  double operator[](int i) const { return e[i]; }

  vec3& operator+=(const vec3& v) {
    e[0] += v.e[0];
    e[1] += v.e[1];
    e[2] += v.e[2];
    return *this;
  }

  double length() const { return std::sqrt(length_squared()); }
  double length_squared() const { return e[0] * e[0] + e[1] * e[1] + e[2] * e[2]; }

  // The book's guard against a Lambertian direction that (almost) cancels the normal.
  bool near_zero() const {
    const double s = 1e-8;
    return std::fabs(e[0]) < s && std::fabs(e[1]) < s && std::fabs(e[2]) < s;
  }
};

using point3 = vec3;
using color = vec3;

inline vec3 operator+(const vec3& u, const vec3& v) {
  return vec3(u.e[0] + v.e[0], u.e[1] + v.e[1], u.e[2] + v.e[2]);
}
inline vec3 operator-(const vec3& u, const vec3& v) {
  return vec3(u.e[0] - v.e[0], u.e[1] - v.e[1], u.e[2] - v.e[2]);
}
inline vec3 operator*(const vec3& u, const vec3& v) {
  return vec3(u.e[0] * v.e[0], u.e[1] * v.e[1], u.e[2] * v.e[2]);
}
inline vec3 operator*(double t, const vec3& v) {
  return vec3(t * v.e[0], t * v.e[1], t * v.e[2]);
}
inline vec3 operator*(const vec3& v, double t) {
  return t * v;
}
inline vec3 operator/(const vec3& v, double t) {
  return (1 / t) * v;
}
inline double dot(const vec3& u, const vec3& v) {
  return u.e[0] * v.e[0] + u.e[1] * v.e[1] + u.e[2] * v.e[2];
}
inline vec3 cross(const vec3& u, const vec3& v) {
  return vec3(u.e[1] * v.e[2] - u.e[2] * v.e[1], u.e[2] * v.e[0] - u.e[0] * v.e[2],
              u.e[0] * v.e[1] - u.e[1] * v.e[0]);
}
inline vec3 unit_vector(const vec3& v) {
  return v / v.length();
}

vec3 from_float(sphray::Vec3 v) {
  return vec3(v.x, v.y, v.z);
}

class ray {
 public:
  ray() = default;
  ray(const point3& origin, const vec3& direction) : orig(origin), dir(direction) {}

  const point3& origin() const { return orig; }
  const vec3& direction() const { return dir; }
  point3 at(double t) const { return orig + t * dir; }

 private:
  point3 orig;
  vec3 dir;
};

// ---- random numbers: the book's random_double, one generator for the one thread ----

std::mt19937_64& generator() {
  static std::mt19937_64 engine;
  return engine;
}

double random_double() {
  static std::uniform_real_distribution<double> distribution(0.0, 1.0);
  return distribution(generator());
}

double random_double(double min, double max) {
  return min + (max - min) * random_double();
}

// Uniform on the unit sphere, by rejection from the cube (the book's v4).
vec3 random_unit_vector() {
  while (true) {
    const vec3 p(random_double(-1, 1), random_double(-1, 1), random_double(-1, 1));
    const double lensq = p.length_squared();
    if (1e-160 < lensq && lensq <= 1) return p / std::sqrt(lensq);
  }
}

vec3 random_in_unit_disk() {
  while (true) {
    const vec3 p(random_double(-1, 1), random_double(-1, 1), 0);
    if (p.length_squared() < 1) return p;
  }
}

vec3 reflect(const vec3& v, const vec3& n) {
  return v - 2 * dot(v, n) * n;
}

vec3 refract(const vec3& uv, const vec3& n, double etai_over_etat) {
  const double cos_theta = std::fmin(dot(-uv, n), 1.0);
  const vec3 r_out_perp = etai_over_etat * (uv + cos_theta * n);
  const vec3 r_out_parallel = -std::sqrt(std::fabs(1.0 - r_out_perp.length_squared())) * n;
  return r_out_perp + r_out_parallel;
}

// ---- hittables: the book's chapter 6 ----

class material;

struct hit_record {
  point3 p;
  vec3 normal;  // against the incoming ray
  const material* mat = nullptr;
  double t = 0;
  bool front_face = false;

  void set_face_normal(const ray& r, const vec3& outward_normal) {
    front_face = dot(r.direction(), outward_normal) < 0;
    normal = front_face ? outward_normal : -outward_normal;
  }
};

class hittable {
 public:
  virtual ~hittable() = default;
  virtual bool hit(const ray& r, double tmin, double tmax, hit_record& rec) const = 0;
};

class sphere : public hittable {
 public:
  sphere(const point3& center, double radius, std::shared_ptr<material> mat)
      : center(center), radius(std::fmax(0, radius)), mat(std::move(mat)) {}

  bool hit(const ray& r, double tmin, double tmax, hit_record& rec) const override {
    const vec3 oc = center - r.origin();
    const double a = r.direction().length_squared();
    const double h = dot(r.direction(), oc);
    const double c = oc.length_squared() - radius * radius;
    const double discriminant = h * h - a * c;
    if (discriminant < 0) return false;
    const double sqrtd = std::sqrt(discriminant);
    // The nearest root in (tmin, tmax).
    double root = (h - sqrtd) / a;
    if (root <= tmin || tmax <= root) {
      root = (h + sqrtd) / a;
      if (root <= tmin || tmax <= root) return false;
    }
    rec.t = root;
    rec.p = r.at(rec.t);
    rec.set_face_normal(r, (rec.p - center) / radius);
    rec.mat = mat.get();
    return true;
  }

 private:
  point3 center;
  double radius;
  std::shared_ptr<material> mat;
};

class hittable_list : public hittable {
 public:
  std::vector<std::shared_ptr<hittable>> objects;

  void add(std::shared_ptr<hittable> object) { objects.push_back(std::move(object)); }

  bool hit(const ray& r, double tmin, double tmax, hit_record& rec) const override {
    hit_record temp_rec;
    bool hit_anything = false;
    double closest_so_far = tmax;
    for (const auto& object : objects) {
      if (object->hit(r, tmin, closest_so_far, temp_rec)) {
        hit_anything = true;
        closest_so_far = temp_rec.t;
        rec = temp_rec;
      }
    }
    return hit_anything;
  }
};

// ---- materials: the book's chapters 10 and 11 ----

class material {
 public:
  virtual ~material() = default;
  virtual bool scatter(const ray& r_in, const hit_record& rec, color& attenuation,
                       ray& scattered) const = 0;
};

class lambertian : public material {
 public:
  explicit lambertian(const color& albedo) : albedo(albedo) {}

  bool scatter(const ray&, const hit_record& rec, color& attenuation,
               ray& scattered) const override {
    vec3 scatter_direction = rec.normal + random_unit_vector();
    if (scatter_direction.near_zero()) scatter_direction = rec.normal;
    scattered = ray(rec.p, scatter_direction);
    attenuation = albedo;
    return true;
  }

 private:
  color albedo;
};

class metal : public material {
 public:
  metal(const color& albedo, double fuzz) : albedo(albedo), fuzz(fuzz < 1 ? fuzz : 1) {}

  bool scatter(const ray& r_in, const hit_record& rec, color& attenuation,
               ray& scattered) const override {
    vec3 reflected = reflect(r_in.direction(), rec.normal);
    reflected = unit_vector(reflected) + (fuzz * random_unit_vector());
    scattered = ray(rec.p, reflected);
    attenuation = albedo;
    return dot(scattered.direction(), rec.normal) > 0;  // absorbed if fuzzed below the surface
  }

 private:
  color albedo;
  double fuzz;
};

class dielectric : public material {
 public:
  explicit dielectric(double refraction_index) : refraction_index(refraction_index) {}

  bool scatter(const ray& r_in, const hit_record& rec, color& attenuation,
               ray& scattered) const override {
    attenuation = color(1.0, 1.0, 1.0);
    const double ri = rec.front_face ? (1.0 / refraction_index) : refraction_index;
    const vec3 unit_direction = unit_vector(r_in.direction());
    const double cos_theta = std::fmin(dot(-unit_direction, rec.normal), 1.0);
    const double sin_theta = std::sqrt(1.0 - cos_theta * cos_theta);
    const bool cannot_refract = ri * sin_theta > 1.0;
    const vec3 direction = cannot_refract || reflectance(cos_theta, ri) > random_double()
                               ? reflect(unit_direction, rec.normal)
                               : refract(unit_direction, rec.normal, ri);
    scattered = ray(rec.p, direction);
    return true;
  }

 private:
  // Schlick's approximation of the reflectance.
  static double reflectance(double cosine, double refraction_index) {
    double r0 = (1 - refraction_index) / (1 + refraction_index);
    r0 = r0 * r0;
    return r0 + (1 - r0) * std::pow((1 - cosine), 5);
  }

  double refraction_index;
};

// ---- the camera: the book's chapters 12 and 13, with the scene's sky ----

struct render_settings {
  int image_width = 0, image_height = 0;
  int samples_per_pixel = 4;
  int max_depth = 50;
};

class camera {
 public:
  camera(const sphray::render::CameraSpec& spec, const sphray::render::Sky& sky,
         const render_settings& settings)
      : settings(settings), horizon(from_float(sky.horizon)), zenith(from_float(sky.zenith)) {
    const point3 lookfrom = from_float(spec.lookfrom);
    const point3 lookat = from_float(spec.lookat);
    const vec3 vup = from_float(spec.vup);
    const double focus_dist = spec.focus_dist;
    defocus_angle = spec.defocus_angle;

    center = lookfrom;
    const double theta = spec.vfov * std::numbers::pi / 180.0;
    const double h = std::tan(theta / 2);
    const double viewport_height = 2 * h * focus_dist;
    const double viewport_width =
        viewport_height * (static_cast<double>(settings.image_width) / settings.image_height);

    const vec3 w = unit_vector(lookfrom - lookat);
    const vec3 u = unit_vector(cross(vup, w));
    const vec3 v = cross(w, u);

    const vec3 viewport_u = viewport_width * u;
    const vec3 viewport_v = viewport_height * -v;  // rows run downwards
    pixel_delta_u = viewport_u / settings.image_width;
    pixel_delta_v = viewport_v / settings.image_height;
    const point3 viewport_upper_left = center - (focus_dist * w) - viewport_u / 2 - viewport_v / 2;
    pixel00_loc = viewport_upper_left + 0.5 * (pixel_delta_u + pixel_delta_v);

    const double defocus_radius =
        focus_dist * std::tan(defocus_angle / 2 * std::numbers::pi / 180.0);
    defocus_disk_u = u * defocus_radius;
    defocus_disk_v = v * defocus_radius;
  }

  // The mean colour of every pixel (linear), rows from the top.
  std::vector<color> render(const hittable& world) {
    std::vector<color> image;
    image.reserve(static_cast<std::size_t>(settings.image_width) *
                  static_cast<std::size_t>(settings.image_height));
    const double pixel_samples_scale = 1.0 / settings.samples_per_pixel;
    for (int j = 0; j < settings.image_height; j++) {
      for (int i = 0; i < settings.image_width; i++) {
        color pixel_color(0, 0, 0);
        for (int sample = 0; sample < settings.samples_per_pixel; sample++) {
          const ray r = get_ray(i, j);
          pixel_color += ray_color(r, settings.max_depth, world);
        }
        image.push_back(pixel_samples_scale * pixel_color);
      }
    }
    return image;
  }

  // Every ray handed to the world's hit(): camera and bounce rays together.
  std::uint64_t rays_traced = 0;

 private:
  // A ray from the lens (the defocus disk) through a point jittered in pixel (i, j).
  ray get_ray(int i, int j) const {
    const vec3 offset(random_double() - 0.5, random_double() - 0.5, 0);
    const point3 pixel_sample =
        pixel00_loc + ((i + offset.x()) * pixel_delta_u) + ((j + offset.y()) * pixel_delta_v);
    const point3 ray_origin = (defocus_angle <= 0) ? center : defocus_disk_sample();
    return ray(ray_origin, pixel_sample - ray_origin);
  }

  point3 defocus_disk_sample() const {
    const vec3 p = random_in_unit_disk();
    return center + (p[0] * defocus_disk_u) + (p[1] * defocus_disk_v);
  }

  color ray_color(const ray& r, int depth, const hittable& world) {
    if (depth <= 0) return color(0, 0, 0);  // the path's rays are spent: no light
    ++rays_traced;
    hit_record rec;
    // 0.001: the book's way of not hitting the surface a ray leaves.
    if (world.hit(r, 0.001, std::numeric_limits<double>::infinity(), rec)) {
      ray scattered;
      color attenuation;
      if (rec.mat->scatter(r, rec, attenuation, scattered))
        return attenuation * ray_color(scattered, depth - 1, world);
      return color(0, 0, 0);
    }
    const vec3 unit_direction = unit_vector(r.direction());
    const double a = 0.5 * (unit_direction.y() + 1.0);
    return (1.0 - a) * horizon + a * zenith;
  }

  render_settings settings;
  color horizon, zenith;
  double defocus_angle = 0;
  point3 center;
  point3 pixel00_loc;
  vec3 pixel_delta_u, pixel_delta_v;
  vec3 defocus_disk_u, defocus_disk_v;
};

// The scene's spheres and materials as the book's objects: one sphere object, and one material
// object, per sphere.
hittable_list make_world(const sphray::render::Scene& scene) {
  hittable_list world;
  for (std::uint32_t id = 0; id < scene.spheres.size(); ++id) {
    const sphray::render::Material m = sphray::render::material_of(scene, id);
    std::shared_ptr<material> mat;
    switch (m.kind) {
      case sphray::render::MaterialKind::lambertian:
        mat = std::make_shared<lambertian>(from_float(m.albedo));
        break;
      case sphray::render::MaterialKind::metal:
        mat = std::make_shared<metal>(from_float(m.albedo), m.fuzz);
        break;
      case sphray::render::MaterialKind::dielectric:
        mat = std::make_shared<dielectric>(m.ior);
        break;
    }
    world.add(std::make_shared<sphere>(from_float(scene.spheres.center(id)),
                                       scene.spheres.radius(id), std::move(mat)));
  }
  return world;
}

// Gamma 2 and the bytes as sphray writes them: int(255.999 c), c clamped to [0, 1].
std::uint8_t to_byte(double linear) {
  const double gamma = linear > 0 ? std::sqrt(linear) : 0.0;
  return static_cast<std::uint8_t>(255.999 * std::clamp(gamma, 0.0, 1.0));
}

// The size asked for: the scene's, or with one side given, the other in the scene's aspect, as
// `sphray render` chooses it.
std::pair<int, int> image_size(int width, int height, const sphray::render::Scene& scene) {
  const auto other_side = [](int given, int scene_given, int scene_other) {
    const long long side = static_cast<long long>(given) * scene_other / scene_given;
    return static_cast<int>(std::clamp<long long>(side, 1, sphray::render::kMaxImageSide));
  };
  const int w = width > 0    ? width
                : height > 0 ? other_side(height, scene.height, scene.width)
                             : scene.width;
  const int h = height > 0  ? height
                : width > 0 ? other_side(width, scene.width, scene.height)
                            : scene.height;
  return {w, h};
}

constexpr int kExitIo = 1, kExitUsage = 2;

int fail(int status, const std::string& message) {
  std::fprintf(stderr, "sphray_book_path: %s\n", message.c_str());
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Path tracing written the way Ray Tracing in One Weekend writes it (double precision, a "
      "virtual hit() per sphere, one ray at a time, one thread): the baseline `sphray render -m "
      "path` is measured against (bench/path_vs_book.py)."};
  std::string scene_name = "rtiow-final";
  std::string output = "book.png";
  int width = 0, height = 0;
  render_settings settings;
  std::uint64_t seed = 0;
  app.add_option("--scene,-s", scene_name, "A preset (see `sphray scenes`) or a .json file")
      ->capture_default_str();
  app.add_option("--width,-W", width, "Image width (default: the scene's)")
      ->check(CLI::Range(1, sphray::render::kMaxImageSide));
  app.add_option("--height,-H", height, "Image height (default: the scene's)")
      ->check(CLI::Range(1, sphray::render::kMaxImageSide));
  app.add_option("--spp", settings.samples_per_pixel, "Samples per pixel, each jittered")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  app.add_option("--max-depth", settings.max_depth, "Rays per path at most")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  app.add_option("--seed", seed, "Seed of the random numbers")->capture_default_str();
  app.add_option("-o,--output", output, "Output image, .png or .ppm")->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitUsage;
  }
  try {
    const sphray::render::Scene scene = sphray::render::load_scene_or_preset(scene_name);
    std::tie(settings.image_width, settings.image_height) = image_size(width, height, scene);
    // Refused before anything is traced, as sphray refuses it.
    sphray::render::PendingImageFile pending(output);
    const hittable_list world = make_world(scene);
    camera cam(scene.camera, scene.sky, settings);
    generator().seed(seed);

    const auto start = std::chrono::steady_clock::now();
    const std::vector<color> pixels = cam.render(world);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    sphray::render::Image image{settings.image_width, settings.image_height,
                                std::vector<std::uint8_t>(3 * pixels.size())};
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      for (int k = 0; k < 3; ++k)
        image.rgb[3 * i + static_cast<std::size_t>(k)] = to_byte(pixels[i][k]);
    }
    pending.commit(image);

    const std::uint64_t camera_rays = static_cast<std::uint64_t>(settings.image_width) *
                                      static_cast<std::uint64_t>(settings.image_height) *
                                      static_cast<std::uint64_t>(settings.samples_per_pixel);
    const double rate = seconds > 0 ? static_cast<double>(cam.rays_traced) / seconds : 0.0;
    std::printf(
        "wrote %s: %dx%d, %d spp, path (the book's way), %.3f s, %.3f Mrays/s (%llu camera + %llu "
        "bounce + 0 shadow rays, brute force)\n",
        output.c_str(), settings.image_width, settings.image_height, settings.samples_per_pixel,
        seconds, rate / 1e6, static_cast<unsigned long long>(camera_rays),
        static_cast<unsigned long long>(cam.rays_traced - camera_rays));
    std::printf(
        "book: max depth %d; one thread, double precision, a virtual hit() per sphere and ray\n",
        settings.max_depth);
    return std::fflush(stdout) == 0 ? 0 : fail(kExitIo, "standard output: cannot write");
  } catch (const sphray::render::SceneError& e) {
    return fail(kExitUsage, e.what());
  } catch (const std::invalid_argument& e) {  // an output refused (OutputRefused), a bad extension
    return fail(kExitUsage, e.what());
  } catch (const std::exception& e) {  // the image cannot be written (IoError), out of memory
    return fail(kExitIo, e.what());
  }
}
