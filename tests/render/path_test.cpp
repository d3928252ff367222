// Path mode against values worked out by hand: the white furnace, one Lambertian bounce under a
// uniform and under a graded sky, glass of index 1, and determinism whatever the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "sphray/render/camera.hpp"
#include "sphray/render/material.hpp"
#include "sphray/render/path_tracer.hpp"
#include "sphray/render/renderer.hpp"

namespace sphray::render {
namespace {

RenderOptions path_options(int width, int height, int spp) {
  RenderOptions o;
  o.mode = Mode::path;
  o.width = width;
  o.height = height;
  o.spp = spp;
  return o;
}

Sky uniform_sky(float radiance) {
  return {{radiance, radiance, radiance}, {radiance, radiance, radiance}};
}

// Every sphere of a preset made of one material.
Scene all_of(const std::string& preset, const Material& material) {
  Scene scene = make_preset(preset);
  scene.materials.assign(scene.spheres.size(), material);
  return scene;
}

const Material kWhite{MaterialKind::lambertian, {1, 1, 1}};

// The white furnace. A path that escapes carries throughput exactly 1 (products of 1.0f) into a
// sky whose radiance is L everywhere (its blend (1 - a) L + a L rounds to within 2 ulp of L),
// so every sample is L, or 0 for a path cut at max depth: the estimator has no variance and the
// Monte Carlo bound is zero. A cut needs 50 rays in a row each hitting another sphere, far
// below 1e-10 for these scenes (a bounce leaves the cluster with probability well above 1/2),
// so every pixel must equal L to float rounding (1e-6 relative).
void expect_furnace(const Scene& scene, float radiance, int threads) {
  RenderOptions o = path_options(32, 18, 4);
  o.threads = threads;
  RenderStats stats;
  const std::vector<Vec3> image = render_radiance(scene, o, {}, &stats);
  ASSERT_EQ(image.size(), 32u * 18u);
  EXPECT_GT(stats.bounce_rays, 0u);  // the spheres were hit, and scattered
  EXPECT_EQ(stats.bvh, scene.spheres.size() >= 128);
  for (std::size_t i = 0; i < image.size(); ++i) {
    ASSERT_NEAR(image[i].x, radiance, 1e-6f * radiance) << "pixel " << i;
    ASSERT_NEAR(image[i].y, radiance, 1e-6f * radiance) << "pixel " << i;
    ASSERT_NEAR(image[i].z, radiance, 1e-6f * radiance) << "pixel " << i;
  }
}

TEST(WhiteFurnace, WhiteLambertianSpheresRenderTheSkyRadiance) {
  Scene scene = all_of("three", kWhite);
  scene.sky = uniform_sky(0.75f);
  expect_furnace(scene, 0.75f, 0);
}

// Two scales and a BVH: the book's ground (radius 1000 at (0, -1000, 0)) under a layer of 225
// spheres of radius 0.3, 2 apart, 3 above it. From the ground a path meets the layer with
// probability about their share of the sky seen from below (7% straight up, more at a slant,
// well under 1/2 with the cosine weighting); from a sphere it reaches the ground or escapes. So
// 50 rays need some 24 ground-layer round trips, probability below 2^-24 per path: the 2304
// samples meet none. (The book's cover itself is no furnace: its spheres rest on the ground, a
// path in the thin gap near a contact needs many bounces, and 0.008% of its paths are cut at
// depth 50; docs/robustness.md, "Touching spheres".)
Scene floating_layer(const Material& material) {
  Scene scene = make_preset("rtiow-final");
  scene.spheres = SphereSoA();
  scene.spheres.add({0, -1000, 0}, 1000.0f);
  for (int i = -7; i <= 7; ++i) {
    for (int k = -7; k <= 7; ++k)
      scene.spheres.add({2.0f * static_cast<float>(i), 3.3f, 2.0f * static_cast<float>(k)}, 0.3f);
  }
  scene.colors.assign(scene.spheres.size(), Vec3{1, 1, 1});
  scene.materials.assign(scene.spheres.size(), material);
  scene.camera = CameraSpec{{0, 10, 25}, {0, 2, 0}, {0, 1, 0}, 45.0f};
  return scene;
}

TEST(WhiteFurnace, HoldsThroughTheBvhAtTwoScales) {
  Scene scene = floating_layer(kWhite);
  ASSERT_GE(scene.spheres.size(), 128u);  // the renderer's BVH threshold
  scene.sky = uniform_sky(2.0f);
  expect_furnace(scene, 2.0f, 2);
}

// The ground alone under a uniform sky, seen from 1.2 above it (issue 32's horizon): a ray that
// grazes the ground from outside is a front face however its normal rounds, so its Lambertian
// bounce leaves upward and escapes, and every pixel is the sky's 0.5 at any depth. (When grazing
// hits were called back faces by the sign of dot(dir, normal), some bounces went into the
// ground and their paths never came back: pixels on the horizon rows came out darker.)
TEST(WhiteFurnace, GrazingHitsOnTheGroundAreFrontFaces) {
  Scene scene = make_preset("single");
  scene.spheres = SphereSoA();
  scene.spheres.add({0, -1000, 0}, 1000.0f);
  scene.colors.assign(1, Vec3{1, 1, 1});
  scene.materials.assign(1, kWhite);
  scene.camera = CameraSpec{{0, 1.2f, 5}, {0, 0.4f, 0}, {0, 1, 0}, 40.0f};
  scene.sky = uniform_sky(0.5f);
  for (int depth : {2, 50}) {
    RenderOptions o = path_options(160, 90, 1024);
    o.max_depth = depth;
    o.seed = 1;
    const std::vector<Vec3> image = render_radiance(scene, o);
    ASSERT_EQ(image.size(), 160u * 90u);
    int darker = 0;
    for (const Vec3& c : image)
      darker += std::fabs(c.x - 0.5f) > 1e-6f * 0.5f ? 1 : 0;
    EXPECT_EQ(darker, 0) << "pixels off the sky's radiance at depth " << depth;
  }
}

// Mirrors and glass of albedo 1 lose nothing either: every scattered path keeps throughput 1.
TEST(WhiteFurnace, MirrorAndGlassLoseNothing) {
  Scene scene = make_preset("three");
  scene.materials = {Material{MaterialKind::dielectric, {1, 1, 1}, 0.0f, 1.5f},
                     Material{MaterialKind::metal, {1, 1, 1}, 0.0f},
                     Material{MaterialKind::dielectric, {1, 1, 1}, 0.0f, 2.4f}};
  scene.sky = uniform_sky(1.0f);
  expect_furnace(scene, 1.0f, 0);
}

// The book's first sphere (centre (0,0,-1), radius 0.5, camera at the origin, vfov 90), albedo
// 0.5, under a uniform sky of 1. A path hitting it scatters once and escapes (a convex sphere
// cannot be met again from outside: spawn()'s guarantee), so it brings 0.5 * 1 = 0.5, and a
// path missing it brings 1. Pixels whose four corners all see the sphere (its outline is an
// ellipse, convex: the whole pixel sees it) must be 0.5; the corner pixels see only sky.
TEST(WhiteFurnace, HalfAlbedoOneBounceGivesHalfTheSky) {
  constexpr int kW = 32, kH = 18;
  Scene scene = all_of("single", Material{MaterialKind::lambertian, {0.5f, 0.5f, 0.5f}});
  scene.sky = uniform_sky(1.0f);
  RenderStats stats;
  const std::vector<Vec3> image = render_radiance(scene, path_options(kW, kH, 8), {}, &stats);
  // The book's viewport: 2 high at distance 1, 2 * kW / kH wide; (u, v) in pixels.
  const auto sees_sphere = [](double u, double v) {
    const double half_width = static_cast<double>(kW) / kH;
    const double dx = -half_width + u * 2 * half_width / kW, dy = 1 - v * 2.0 / kH, dz = -1;
    const double b = -dz;  // dot(d, centre), centre (0, 0, -1)
    const double a = dx * dx + dy * dy + dz * dz;
    return b * b - a * (1.0 - 0.25) > 1e-9;
  };
  int inside = 0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const Vec3 c = image[static_cast<std::size_t>(y) * kW + x];
      EXPECT_GE(c.x, 0.5f - 1e-6f);
      EXPECT_LE(c.x, 1.0f + 1e-6f);
      if (sees_sphere(x, y) && sees_sphere(x + 1, y) && sees_sphere(x, y + 1) &&
          sees_sphere(x + 1, y + 1)) {
        ++inside;
        EXPECT_NEAR(c.x, 0.5f, 1e-6f) << x << "," << y;
        EXPECT_NEAR(c.z, 0.5f, 1e-6f) << x << "," << y;
      }
    }
  }
  EXPECT_GT(inside, 40);
  for (int corner : {0, kW - 1, (kH - 1) * kW, kH * kW - 1})
    EXPECT_NEAR(image[static_cast<std::size_t>(corner)].y, 1.0f, 1e-6f);
  // Max depth 1: the camera rays alone, so the sphere gives nothing back.
  RenderOptions camera_only = path_options(kW, kH, 1);
  camera_only.max_depth = 1;
  RenderStats only_stats;
  const std::vector<Vec3> dark = render_radiance(scene, camera_only, {}, &only_stats);
  EXPECT_EQ(only_stats.bounce_rays, 0u);
  EXPECT_EQ(dark[static_cast<std::size_t>(kH / 2) * kW + kW / 2], (Vec3{0, 0, 0}));
  EXPECT_GT(stats.bounce_rays, 0u);
  EXPECT_LT(stats.bounce_rays, stats.camera_rays);  // only the hits bounce, once
}

// A Lambertian sphere of albedo rho under the sky L(d) = (d.y + 1) / 2 (horizon 0, zenith 1):
// the outgoing radiance at normal n is rho/pi times the cosine-weighted integral of L over the
// hemisphere, rho (1 + (2/3) n.y) / 2, since the integral of d cos over the hemisphere is
// (2 pi / 3) n. Seen head-on (n.y = 0) that is 0.25 for rho = 0.5; from above (n.y = 1),
// 0.41667 (uniform hemisphere sampling would give 0.375). Each sample is rho L(d): its standard
// deviation is rho/2 sqrt(E[d.y^2] - E[d.y]^2) = 0.25 * 0.5 = 0.125 head-on (E[d.y^2] = 1/4)
// and 0.25 * sqrt(1/2 - 4/9) = 0.059 from above. The image mean of 16 * 16 * 16 samples has a
// deviation of at most 0.125 / 64 = 0.002: the bound is five of them, 0.01. The camera's narrow
// view (2 degrees) keeps every normal within 0.02 of n, which moves the mean by < 0.004.
void expect_graded_sky_mean(CameraSpec camera, double expected) {
  Scene scene = all_of("single", Material{MaterialKind::lambertian, {0.5f, 0.5f, 0.5f}});
  scene.sky = Sky{{0, 0, 0}, {1, 1, 1}};
  scene.camera = camera;
  const std::vector<Vec3> image = render_radiance(scene, path_options(16, 16, 16));
  double sum = 0;
  for (const Vec3& c : image)
    sum += c.y;
  EXPECT_NEAR(sum / static_cast<double>(image.size()), expected, 0.01 + 0.004);
}

TEST(LambertianBounce, HeadOnUnderAGradedSkyMatchesTheIntegral) {
  expect_graded_sky_mean(CameraSpec{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 2.0f}, 0.25);
}

TEST(LambertianBounce, FromAboveUnderAGradedSkyMatchesTheCosineIntegral) {
  expect_graded_sky_mean(CameraSpec{{0, 1, -1}, {0, 0, -1}, {1, 0, 0}, 2.0f},
                         0.5 * (1 + 2.0 / 3.0) / 2);
}

// Glass of index 1 is no interface: the image is the bare sky's, to the float rounding of the
// spawn offset and the refracted direction.
TEST(Dielectric, GlassOfIndexOneRendersAsIfAbsent) {
  Scene glass = all_of("three", Material{MaterialKind::dielectric, {1, 1, 1}, 0.0f, 1.0f});
  Scene empty = glass;
  empty.spheres = SphereSoA();
  empty.materials.clear();
  empty.colors.clear();
  const RenderOptions o = path_options(32, 18, 2);
  RenderStats stats;
  const std::vector<Vec3> through = render_radiance(glass, o, {}, &stats);
  const std::vector<Vec3> sky = render_radiance(empty, o);
  EXPECT_GT(stats.bounce_rays, 0u);  // into the spheres and out
  for (std::size_t i = 0; i < sky.size(); ++i) {
    EXPECT_NEAR(through[i].x, sky[i].x, 1e-4f) << "pixel " << i;
    EXPECT_NEAR(through[i].y, sky[i].y, 1e-4f) << "pixel " << i;
    EXPECT_NEAR(through[i].z, sky[i].z, 1e-4f) << "pixel " << i;
  }
}

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

TEST(PathDeterminism, SameBitsWhateverTheThreadCount) {
  const Scene scene = make_preset("rtiow-final");
  RenderOptions o = path_options(40, 24, 2);  // 3 x 2 tiles, the last ones partial
  o.seed = 12;
  o.threads = 1;
  const std::vector<Vec3> one = render_radiance(scene, o);
  for (int threads : {2, 3, 0}) {
    o.threads = threads;
    EXPECT_TRUE(same_bits(one, render_radiance(scene, o))) << threads << " threads";
  }
  o.seed = 13;
  EXPECT_FALSE(same_bits(one, render_radiance(scene, o)));
  o.seed = 12;
  o.accel = Accel::brute_force;  // the tree and brute force report the same hits
  EXPECT_TRUE(same_bits(one, render_radiance(scene, o)));
}

// One path with the one-path functions, as the renderer traced them before its wavefront: the
// light that sample `sample` of pixel (x, y) brings.
Vec3 one_path(const Scene& scene, const Camera& camera, const RenderOptions& o, int x, int y,
              std::uint32_t sample) {
  const SphereView view = scene.spheres.view();
  PathRandom random(o.seed, static_cast<std::uint64_t>(y) * o.width + x, sample);
  const float px = static_cast<float>(x) + random.uniform();
  const float py = static_cast<float>(y) + random.uniform();
  Ray ray = camera.ray(px, py);
  if (camera.has_defocus()) {
    const Vec3 lens = random.in_unit_disk();
    ray = camera.ray(px, py, lens.x, lens.y);
  }
  Vec3 throughput{1, 1, 1};
  for (int depth = 0; depth < o.max_depth; ++depth) {
    const Hit hit = intersect(view, ray);
    if (!hit.found()) return throughput * scene.sky.radiance(ray.dir);
    const Surface at = surface(view, ray, hit);
    const auto scattered = scatter(material_of(scene, hit.id), ray.dir, at, random);
    if (!scattered) break;
    throughput = throughput * scattered->attenuation;
    ray = spawn(at, scattered->direction);
  }
  return {0, 0, 0};
}

// The whole tracer against paths traced one at a time, each pixel's samples summed in sample
// order: the same bits, with many samples per pass (paths of later samples taking the lanes of
// ended ones) and partial tiles, and with a depth limit that cuts paths at different rounds.
void expect_same_as_one_path_at_a_time(const Scene& scene, RenderOptions o) {
  const Camera camera(scene.camera, o.width, o.height);
  const std::vector<Vec3> image = render_radiance(scene, o);
  std::vector<Vec3> expected;
  for (int y = 0; y < o.height; ++y) {
    for (int x = 0; x < o.width; ++x) {
      Vec3 sum{0, 0, 0};
      for (int s = 0; s < o.spp; ++s)
        sum += one_path(scene, camera, o, x, y, static_cast<std::uint32_t>(s));
      expected.push_back(sum * (1.0f / static_cast<float>(o.spp)));
    }
  }
  EXPECT_TRUE(same_bits(expected, image));
}

TEST(PathDeterminism, SameBitsAsOnePathAtATime) {
  RenderOptions o = path_options(40, 24, 21);  // 3 x 2 tiles, 21 samples: more than one pass
  o.seed = 5;
  o.threads = 2;
  expect_same_as_one_path_at_a_time(make_preset("rtiow-final"), o);
  o.max_depth = 3;
  expect_same_as_one_path_at_a_time(make_preset("rtiow-final"), o);
  o.spp = 3;
  expect_same_as_one_path_at_a_time(make_preset("random:300"), o);
}

// A time limit that is up at once still leaves one full sample for every pixel: the image is
// the 1-spp image, bit for bit.
TEST(PathTimeLimit, StopsBetweenSamplesWithEqualSamplesEverywhere) {
  const Scene scene = make_preset("three");
  RenderOptions limited = path_options(32, 18, 64);
  limited.time_limit = 1e-9;
  RenderStats stats;
  const Image a = render(scene, limited, {}, &stats);
  EXPECT_EQ(stats.spp, 1);
  EXPECT_EQ(stats.camera_rays, 32u * 18u);
  const Image b = render(scene, path_options(32, 18, 1));
  EXPECT_EQ(a.rgb, b.rgb);
}

TEST(PathProgress, CountsTilesTimesSamplesAndRaysOfEveryKind) {
  RenderOptions o = path_options(40, 20, 3);
  RenderStats stats;
  std::atomic<std::size_t> calls{0}, last_total{0};
  std::atomic<std::uint64_t> most_camera{0}, most_bounce{0};
  render(
      make_preset("three"), o,
      [&](std::size_t, std::size_t total, const RayCounts& rays) {
        ++calls;
        last_total = total;
        most_camera = std::max<std::uint64_t>(most_camera, rays.camera);
        most_bounce = std::max<std::uint64_t>(most_bounce, rays.bounce);
        EXPECT_EQ(rays.shadow, 0u);
      },
      &stats);
  // Once when the tracing starts, then for each of ceil(40/16) * ceil(20/16) tiles once for its
  // 3 samples; the count is of tiles times samples.
  EXPECT_EQ(calls, 1u + 3u * 2u);
  EXPECT_EQ(last_total, 18u);
  EXPECT_EQ(stats.camera_rays, 40u * 20u * 3u);
  EXPECT_EQ(most_camera, stats.camera_rays);
  EXPECT_EQ(most_bounce, stats.bounce_rays);
  EXPECT_GT(stats.bounce_rays, 0u);
  EXPECT_EQ(stats.spp, 3);
}

TEST(PathOptions, BadDepthAndTimeLimitAreRefused) {
  const Scene scene = make_preset("single");
  RenderOptions o = path_options(8, 8, 1);
  o.max_depth = 0;
  EXPECT_THROW(render(scene, o), std::invalid_argument);
  o.max_depth = 50;
  o.time_limit = -1;
  EXPECT_THROW(render(scene, o), std::invalid_argument);
  o.time_limit = NAN;
  EXPECT_THROW(render(scene, o), std::invalid_argument);
}

}  // namespace
}  // namespace sphray::render
