// A scene float cannot render: a 1 mm sphere resting on a 10 km ground, 36 km from the origin
// of coordinates (a survey's or a city model's units: metres), seen from a camera 6 mm beside
// it. The same camera rays are traced twice, in float (left half) and in double (right half),
// and each hit shaded by its normal. At 3e4 and 2e4 float's spacing is 1/512 m, twice the
// sphere's radius: float cannot even place it. Writes one PNG (docs/gallery.md).
//
//   sphray_precision_demo [-o FILE] [-W WIDTH] [-H HEIGHT]   (each half WIDTH x HEIGHT)
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>

#include "sphray/render/image_file.hpp"
#include "sphray/sphray.hpp"

namespace {

using sphray::Vec3d;

// The ground's top, where the small sphere rests.
constexpr Vec3d kContact{30000.0, 0.0, 20000.0};
constexpr double kGroundRadius = 1e4;  // 10 km
constexpr double kRadius = 1e-3;       // 1 mm

struct Scene {
  double cx[2], cy[2], cz[2], r[2];
  Scene() {
    const Vec3d ground = kContact - Vec3d{0, kGroundRadius, 0};
    const Vec3d ball = kContact + Vec3d{0, kRadius, 0};
    cx[0] = ground.x, cy[0] = ground.y, cz[0] = ground.z, r[0] = kGroundRadius;
    cx[1] = ball.x, cy[1] = ball.y, cz[1] = ball.z, r[1] = kRadius;
  }
  sphray::SphereViewd view() const { return {cx, cy, cz, r, 2}; }
};

// A pinhole camera 6 mm from the small sphere and 1.5 mm above the ground, looking at it.
struct Camera {
  Vec3d eye, corner, across, up;
  Camera(int width, int height) {
    const Vec3d target = kContact + Vec3d{0, 0.8 * kRadius, 0};
    eye = kContact + Vec3d{-0.0042, 0.0015, -0.0042};
    const Vec3d w = normalize(eye - target);
    const Vec3d u = normalize(cross(Vec3d{0, 1, 0}, w));
    const Vec3d v = cross(w, u);
    const double half_height = std::tan(0.5 * 40.0 * 3.141592653589793 / 180.0);
    const double half_width = half_height * width / height;
    across = 2 * half_width * u;
    up = 2 * half_height * v;
    corner = -half_width * u - half_height * v - w;
  }
  sphray::Rayd ray(double s, double t) const { return {eye, corner + s * across + t * up}; }
};

std::uint8_t byte(double x) {
  return static_cast<std::uint8_t>(std::lround(255.0 * std::fmin(1.0, std::fmax(0.0, x))));
}

// The colour of a pixel: the normal's components from [-1, 1] to [0, 1], or the sky.
template <class Surface>
void shade(bool hit, const Surface& s, double sky_y, std::uint8_t* rgb) {
  if (!hit) {
    const double a = 0.5 * (sky_y + 1.0);
    rgb[0] = byte((1 - a) + a * 0.5), rgb[1] = byte((1 - a) + a * 0.7), rgb[2] = byte(1.0);
    return;
  }
  rgb[0] = byte(0.5 * (s.normal.x + 1)), rgb[1] = byte(0.5 * (s.normal.y + 1));
  rgb[2] = byte(0.5 * (s.normal.z + 1));
}

sphray::Vec3 to_float(Vec3d v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"A 1 mm sphere on a 10 km ground, 36 km from the origin, in float and double"};
  std::string output = "precision.png";
  int width = 480, height = 320;
  app.add_option("-o,--output", output, "the PNG to write (left: float, right: double)");
  app.add_option("-W,--width", width, "each half's width")->check(CLI::Range(8, 4096));
  app.add_option("-H,--height", height, "each half's height")->check(CLI::Range(8, 4096));
  CLI11_PARSE(app, argc, argv);
  try {
    const Scene scene;
    const sphray::SphereViewd doubles = scene.view();
    float fx[2], fy[2], fz[2], fr[2];
    for (int i = 0; i < 2; ++i) {
      fx[i] = static_cast<float>(scene.cx[i]), fy[i] = static_cast<float>(scene.cy[i]);
      fz[i] = static_cast<float>(scene.cz[i]), fr[i] = static_cast<float>(scene.r[i]);
    }
    const sphray::SphereView floats{fx, fy, fz, fr, 2};
    const Camera camera(width, height);
    sphray::render::Image image{2 * width, height, {}};
    image.rgb.resize(static_cast<std::size_t>(3 * 2 * width * height));
    std::size_t hits[2] = {0, 0};
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const sphray::Rayd ray =
            camera.ray((x + 0.5) / width, 1.0 - (y + 0.5) / height);  // row 0 at the top
        const double sky_y = normalize(ray.dir).y;
        std::uint8_t* left = &image.rgb[3 * (static_cast<std::size_t>(y) * 2 * width + x)];
        const sphray::Ray f{to_float(ray.origin), to_float(ray.dir)};
        const sphray::Hit fh = sphray::intersect(floats, f);
        shade(fh.id == 1, sphray::surface(floats, f, fh), sky_y, left);
        const sphray::Hitd dh = sphray::intersect(doubles, ray);
        shade(dh.id == 1, sphray::surface(doubles, ray, dh), sky_y, left + 3 * width);
        hits[0] += fh.id == 1 ? 1 : 0;
        hits[1] += dh.id == 1 ? 1 : 0;
        if (fh.id == 0) left[0] = left[1] = left[2] = 90;  // the ground: grey in both halves
        if (dh.id == 0) left[3 * width] = left[3 * width + 1] = left[3 * width + 2] = 90;
      }
    }
    sphray::render::write_image(image, output);
    std::printf("wrote %s: %dx%d; pixels on the 1 mm sphere: float %zu, double %zu\n",
                output.c_str(), 2 * width, height, hits[0], hits[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sphray_precision_demo: %s\n", e.what());
    return 1;
  }
  return 0;
}
