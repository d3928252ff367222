// Rendered pixels against colours computed here from the formulas (the book's camera, the
// ray-sphere quadratic, the sky gradient), never from the renderer's own helpers.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <utility>

#include "sphray/render/renderer.hpp"

namespace sphray::render {
namespace {

struct Rgb {
  int r, g, b;
};

Rgb pixel(const Image& image, int x, int y) {
  const std::uint8_t* p = &image.rgb[3 * (static_cast<std::size_t>(y) * image.width + x)];
  return {p[0], p[1], p[2]};
}

// The book's conversion, written out: int(255.999 * c).
int byte_of(double c) {
  return static_cast<int>(255.999 * c);
}

void expect_rgb(Rgb actual, double r, double g, double b, int tolerance = 1) {
  EXPECT_NEAR(actual.r, byte_of(r), tolerance);
  EXPECT_NEAR(actual.g, byte_of(g), tolerance);
  EXPECT_NEAR(actual.b, byte_of(b), tolerance);
}

RenderOptions options(Mode mode, int width, int height) {
  RenderOptions o;
  o.mode = mode;
  o.width = width;
  o.height = height;
  return o;
}

// Chapter 5's ray through the centre of pixel (x, y), in double.
struct Dir {
  double x, y, z;
};
Dir single_ray(int x, int y, int width, int height) {
  double half_width = static_cast<double>(width) / height;
  return {-half_width + (x + 0.5) * 2 * half_width / width, 1 - (y + 0.5) * 2.0 / height, -1};
}

// White to (0.5, 0.7, 1.0) by a = 0.5 * (unit(dir).y + 1).
void expect_sky(Rgb actual, Dir d) {
  double a = 0.5 * (d.y / std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z) + 1);
  expect_rgb(actual, 1 - a + a * 0.5, 1 - a + a * 0.7, 1.0);
}

// The discriminant of |t d - (0,0,-1)|^2 = 0.25 over 4: the single sphere is hit when > 0.
double single_discriminant(Dir d) {
  double b = d.z * -1.0;  // dot(d, centre - origin)
  double a = d.x * d.x + d.y * d.y + d.z * d.z;
  return b * b - a * (1.0 - 0.25);
}

TEST(Render, ImageHasTheAskedSize) {
  Image image = render(make_preset("single"), options(Mode::normals, 37, 21));
  EXPECT_EQ(image.width, 37);
  EXPECT_EQ(image.height, 21);
  EXPECT_EQ(image.rgb.size(), 37u * 21u * 3u);
}

// With an odd size the centre pixel's centre is the image centre: the ray is (0,0,-1) and
// meets the sphere where its normal is (0,0,1), coloured 0.5 * (n + 1) = (0.5, 0.5, 1).
TEST(Render, SingleCentreShowsTheNormalFacingTheCamera) {
  Image image = render(make_preset("single"), options(Mode::normals, 401, 225));
  expect_rgb(pixel(image, 200, 112), 0.5, 0.5, 1.0, 0);
}

TEST(Render, TopRowIsTheSkyGradient) {
  Image image = render(make_preset("single"), options(Mode::normals, 400, 225));
  for (int x : {0, 100, 200, 399})
    expect_sky(pixel(image, x, 0), single_ray(x, 0, 400, 225));
}

// An off-centre hit: the normal is (p - c) / r with p on the ray at the near root.
TEST(Render, SingleNormalAwayFromTheCentre) {
  int w = 400, h = 225, x = 230, y = 90;
  Dir d = single_ray(x, y, w, h);
  double a = d.x * d.x + d.y * d.y + d.z * d.z;
  double t = (d.z * -1.0 - std::sqrt(single_discriminant(d))) / a;
  double n[3] = {t * d.x / 0.5, t * d.y / 0.5, (t * d.z + 1) / 0.5};
  Image image = render(make_preset("single"), options(Mode::normals, w, h));
  expect_rgb(pixel(image, x, y), 0.5 * (n[0] + 1), 0.5 * (n[1] + 1), 0.5 * (n[2] + 1));
}

// Every pixel clearly inside the disc is the sphere's colour, single's red (1, 0, 0), every one
// clearly outside is sky.
TEST(Render, FlatIsRedOnTheSphereAndSkyElsewhere) {
  int w = 160, h = 90;
  Image image = render(make_preset("single"), options(Mode::flat, w, h));
  int red = 0, sky = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      Dir d = single_ray(x, y, w, h);
      double disc = single_discriminant(d);
      if (disc > 1e-3) {
        expect_rgb(pixel(image, x, y), 1, 0, 0, 0);
        ++red;
      } else if (disc < -1e-3) {
        expect_sky(pixel(image, x, y), d);
        ++sky;
      }
    }
  }
  EXPECT_GT(red, 1000);
  EXPECT_GT(sky, 5000);
}

// The pixel that the point p projects to through the `three` preset's camera (lookfrom
// (0.5, 1.5, 7), lookat (0, -0.2, 0.3), vup +y, vfov 32): the book's frame (w back, u right,
// v up) and a viewport at distance 1, 2 tan(16 degrees) high, in double.
std::pair<int, int> three_pixel(Dir p, int width, int height) {
  auto sub = [](Dir a, Dir b) { return Dir{a.x - b.x, a.y - b.y, a.z - b.z}; };
  auto dot = [](Dir a, Dir b) { return a.x * b.x + a.y * b.y + a.z * b.z; };
  auto cross = [](Dir a, Dir b) {
    return Dir{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  };
  auto unit = [&](Dir a) {
    double l = std::sqrt(dot(a, a));
    return Dir{a.x / l, a.y / l, a.z / l};
  };
  const Dir from{0.5, 1.5, 7}, at{0, -0.2, 0.3};
  const Dir w = unit(sub(from, at)), u = unit(cross(Dir{0, 1, 0}, w)), v = cross(w, u);
  const Dir d = sub(p, from);
  const double scale = height / (2 * std::tan(16 * std::numbers::pi / 180) * -dot(d, w));
  return {static_cast<int>(width / 2.0 + dot(d, u) * scale),
          static_cast<int>(height / 2.0 - dot(d, v) * scale)};
}

// Flat: each hit is its own sphere's colour, unshaded. The pixel of each of `three`'s centres
// (presets.cpp: red, blue, green) is that sphere's colour exactly.
TEST(Render, FlatPaintsEachSphereItsOwnColour) {
  const int w = 160, h = 90;
  Image image = render(make_preset("three"), options(Mode::flat, w, h));
  const Dir centres[3] = {{0, 0, 0}, {-2.2, -0.3, 0.5}, {2, -0.5, 1}};
  const double colours[3][3] = {{0.9, 0.15, 0.1}, {0.15, 0.3, 0.9}, {0.15, 0.8, 0.2}};
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE(k);
    auto [x, y] = three_pixel(centres[k], w, h);
    expect_rgb(pixel(image, x, y), colours[k][0], colours[k][1], colours[k][2], 0);
  }
}

// The centre ray hits at distance 0.5; the camera is 1 from what it looks at: 1 / (1 + 0.5).
TEST(Render, DepthIsNearBrightScaledToTheCamera) {
  Image image = render(make_preset("single"), options(Mode::depth, 401, 225));
  expect_rgb(pixel(image, 200, 112), 2.0 / 3, 2.0 / 3, 2.0 / 3);
  expect_rgb(pixel(image, 0, 0), 0, 0, 0, 0);
}

TEST(Render, IdGivesEachSphereItsOwnColour) {
  Scene scene = make_preset("three");
  Image image = render(scene, options(Mode::id, 160, 90));
  // The red sphere (id 0) is near the middle, the blue one (id 1) to the left.
  Rgb middle = pixel(image, 80, 45), left = pixel(image, 20, 55), corner = pixel(image, 0, 0);
  EXPECT_TRUE(middle.r != left.r || middle.g != left.g || middle.b != left.b);
  EXPECT_GT(middle.r + middle.g + middle.b, 0);
  expect_rgb(corner, 0, 0, 0, 0);
  Image again = render(scene, options(Mode::id, 160, 90));
  EXPECT_EQ(image.rgb, again.rgb);
}

// Shaded: albedo * (0.15 + 0.85 * max(0, n . L)) when the sun is visible, 0.15 * albedo in
// shadow, then gamma 2; L = unit(0.6, 1, 0.45).
double sun_cosine_for_normal_z() {
  return 0.45 / std::sqrt(0.6 * 0.6 + 1.0 + 0.45 * 0.45);
}

TEST(Render, ShadedLitByTheSun) {
  Image image = render(make_preset("single"), options(Mode::shaded, 401, 225));
  double lit = 0.15 + 0.85 * sun_cosine_for_normal_z();
  expect_rgb(pixel(image, 200, 112), std::sqrt(lit), 0, 0);
}

TEST(Render, ShadedInTheShadowOfABlocker) {
  // The camera sees (0,0,-2) on a sphere at (0,0,-3); a small sphere sits on the way from that
  // point to the sun, off the line of sight.
  Scene scene;
  scene.spheres.add({0, 0, -3}, 1.0f);
  scene.colors.push_back({0, 1, 0});
  double l = std::sqrt(0.6 * 0.6 + 1.0 + 0.45 * 0.45);
  scene.spheres.add(
      {static_cast<float>(0.6 / l), static_cast<float>(1.0 / l), static_cast<float>(-2 + 0.45 / l)},
      0.2f);
  scene.colors.push_back({1, 1, 1});
  Image image = render(scene, options(Mode::shaded, 401, 225));
  expect_rgb(pixel(image, 200, 112), 0, std::sqrt(0.15), 0);
  scene.spheres.set(1, {5, 5, 5}, 0.2f);  // blocker moved away: lit again
  Image lit = render(scene, options(Mode::shaded, 401, 225));
  expect_rgb(pixel(lit, 200, 112), 0, std::sqrt(0.15 + 0.85 * sun_cosine_for_normal_z()), 0);
}

TEST(Render, SameImageForAnyThreadCount) {
  Scene scene = make_preset("rtiow-final");
  for (Mode mode : {Mode::normals, Mode::shaded}) {
    RenderOptions o = options(mode, 203, 117);  // partial tiles on both edges
    o.spp = 3;
    o.seed = 7;
    o.threads = 1;
    Image one = render(scene, o);
    o.threads = 2;
    Image two = render(scene, o);
    o.threads = 4;
    Image four = render(scene, o);
    EXPECT_EQ(one.rgb, two.rgb) << mode_name(mode);
    EXPECT_EQ(one.rgb, four.rgb) << mode_name(mode);
  }
}

// The kernel promises the BVH finds the same hits as brute force: the images must agree.
TEST(Render, BvhAndBruteForceGiveTheSameImage) {
  for (const char* name : {"rtiow-final", "random:3000"}) {
    Scene scene = make_preset(name);
    for (Mode mode : {Mode::id, Mode::shaded}) {
      RenderOptions o = options(mode, 160, 90);
      o.accel = Accel::brute_force;
      Image brute = render(scene, o);
      o.accel = Accel::bvh;
      RenderStats stats;
      Image bvh = render(scene, o, {}, &stats);
      EXPECT_TRUE(stats.bvh);
      EXPECT_EQ(brute.rgb, bvh.rgb) << name << " " << mode_name(mode);
    }
  }
}

TEST(Render, TheSeedMovesTheJitter) {
  Scene scene = make_preset("three");
  RenderOptions o = options(Mode::normals, 64, 36);
  o.spp = 4;
  Image a = render(scene, o);
  EXPECT_EQ(a.rgb, render(scene, o).rgb);
  o.seed = 1;
  EXPECT_NE(a.rgb, render(scene, o).rgb);  // the spheres' edges are sampled elsewhere
}

TEST(Render, ReportsRaysAndProgress) {
  RenderOptions o = options(Mode::shaded, 40, 20);
  o.spp = 2;
  RenderStats stats;
  std::atomic<std::size_t> calls{0}, last_total{0}, first_done{99};
  render(
      make_preset("single"), o,
      [&](std::size_t done, std::size_t total, const RayCounts& rays) {
        if (calls++ == 0) first_done = done;
        last_total = total;
        EXPECT_LE(rays.camera, 40u * 20u * 2u);
        EXPECT_EQ(rays.bounce, 0u);
      },
      &stats);
  EXPECT_EQ(stats.camera_rays, 40u * 20u * 2u);
  EXPECT_GT(stats.shadow_rays, 0u);
  // Once when the tracing starts (done 0), then once per tile: ceil(40/16) * ceil(20/16).
  EXPECT_EQ(first_done, 0u);
  EXPECT_EQ(calls, 1u + 3u * 2u);
  EXPECT_EQ(last_total, 6u);
}

TEST(Render, RefusesBadOptions) {
  Scene scene = make_preset("single");
  RenderOptions o = options(Mode::normals, 0, 10);
  EXPECT_THROW(render(scene, o), std::invalid_argument);
  o = options(Mode::normals, 10, 10);
  o.spp = 0;
  EXPECT_THROW(render(scene, o), std::invalid_argument);
  o.spp = 1;
  o.threads = -1;
  EXPECT_THROW(render(scene, o), std::invalid_argument);
}

TEST(Modes, NamesRoundTrip) {
  for (const std::string& name : mode_names())
    EXPECT_EQ(mode_name(*parse_mode(name)), name);
  EXPECT_FALSE(parse_mode("normal"));
}

}  // namespace
}  // namespace sphray::render
