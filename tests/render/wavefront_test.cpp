// The path tracer's wavefront shading (render/src/path/wavefront.hpp), each instruction set's copy,
// against the one-path functions it stands for: sphray::surface, scatter and sphray::spawn,
// Sky::radiance and PathRandom. Every bounce of every path must agree bit for bit (next ray,
// throughput, random counter, the sky light a miss brings), so that the images stay what the
// one-path renderer made.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "path/wavefront.hpp"
#include "sphray/render/camera.hpp"
#include "sphray/render/renderer.hpp"

namespace sphray::render {
namespace {

std::uint32_t bits(float x) {
  return std::bit_cast<std::uint32_t>(x);
}

void expect_same(Vec3 expected, Vec3 actual, const char* what, std::size_t lane) {
  EXPECT_EQ(bits(expected.x), bits(actual.x)) << what << ", lane " << lane;
  EXPECT_EQ(bits(expected.y), bits(actual.y)) << what << ", lane " << lane;
  EXPECT_EQ(bits(expected.z), bits(actual.z)) << what << ", lane " << lane;
}

// One path as the one-path renderer keeps it.
struct Path {
  Ray ray;
  Vec3 throughput;
  PathRandom random;
  std::uint16_t slot;
  std::int32_t rays_left;  // this one included
};

// Advances the paths one bounce with the one-path functions, as the renderer did before the
// wavefront: misses add sky light, hits scatter and spawn, absorbed paths leave.
std::vector<Path> reference_bounce(const Scene& scene, const std::vector<Path>& paths,
                                   std::vector<Vec3>& radiance) {
  const SphereView view = scene.spheres.view();
  std::vector<Path> next;
  for (const Path& path : paths) {
    const Hit hit = intersect(view, path.ray);
    if (!hit.found()) {
      radiance[path.slot] += path.throughput * scene.sky.radiance(path.ray.dir);
      continue;
    }
    const Surface s = surface(view, path.ray, hit);
    PathRandom random = path.random;
    const auto scattered = scatter(material_of(scene, hit.id), path.ray.dir, s, random);
    if (!scattered || path.rays_left == 1) continue;  // absorbed, or its last ray traced
    next.push_back({spawn(s, scattered->direction), path.throughput * scattered->attenuation,
                    random, path.slot, path.rays_left - 1});
  }
  return next;
}

// Camera rays through random points of the image, with random throughputs: many bounces of them
// meet every material from both sides.
std::vector<Path> start(const Scene& scene, std::uint64_t seed) {
  const Camera camera(scene.camera, 160, 90);
  std::vector<Path> paths;
  for (std::uint16_t i = 0; i < kWavefront; ++i) {
    PathRandom random(seed, i, 7);
    const float px = 160.0f * random.uniform(), py = 90.0f * random.uniform();
    const Vec3 throughput{random.uniform(), random.uniform(), random.uniform()};
    // Some paths run out of rays before the test's 12 bounces are up.
    const std::int32_t rays_left = 4 + i % 16;
    paths.push_back({camera.ray(px, py), throughput, random, i, rays_left});
  }
  return paths;
}

// Sky::radiance's blend for a direction, as the record of a path keeps it for its ray.
float sky_blend(Vec3 dir) {
  return 0.5f * (dir.y / length(dir) + 1.0f);
}

PathRecord record(const Path& path) {
  const std::uint64_t counter = path.random.counter();
  return {path.throughput.x,
          path.throughput.y,
          path.throughput.z,
          path.rays_left,
          path.slot,
          static_cast<std::uint32_t>(counter),
          static_cast<std::uint32_t>(counter >> 32),
          sky_blend(path.ray.dir)};
}

// The paths into the first lanes; the lanes past them poisoned. The passes also compute the lanes
// just past the live ones (wavefront_passes.cpp): these must change nothing a live path or the
// light reads. A poisoned lane hits sphere 0 and would live on, and its entry is out of bounds.
void load(const std::vector<Path>& paths, Wavefront& w) {
  w.live = paths.size();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const PathRecord poison{nan, nan, nan, 1000, 0x7fffffffu, ~0u, ~0u, nan};
  for (std::size_t k = 0; k < kWavefront; ++k) {
    const bool live = k < paths.size();
    w.rays[k] = live ? paths[k].ray : Ray{{nan, 1e30f, -1e30f}, {nan, 0.0f, 0.0f}, nan, nan};
    w.hits[k] = Hit{nan, 0};  // the live lanes' are the kernel's
    w.paths[k] = live ? record(paths[k]) : poison;
  }
}

void expect_same(const std::vector<Path>& expected, const Wavefront& w) {
  ASSERT_EQ(expected.size(), w.live);
  for (std::size_t k = 0; k < w.live; ++k) {
    expect_same(expected[k].ray.origin, w.rays[k].origin, "origin", k);
    expect_same(expected[k].ray.dir, w.rays[k].dir, "direction", k);
    EXPECT_EQ(w.rays[k].tmin, 0.0f);
    EXPECT_EQ(w.rays[k].tmax, INFINITY);
    const PathRecord& path = w.paths[k];
    expect_same(expected[k].throughput, {path.tr, path.tg, path.tb}, "throughput", k);
    EXPECT_EQ(expected[k].random.counter(), path.counter()) << "lane " << k;
    EXPECT_EQ(expected[k].slot, path.slot) << "lane " << k;
    EXPECT_EQ(expected[k].rays_left, path.rays_left) << "lane " << k;
    EXPECT_EQ(bits(sky_blend(expected[k].ray.dir)), bits(path.sky)) << "sky blend, lane " << k;
  }
}

void expect_bounces_agree(const Scene& scene, std::uint64_t seed, ShadeFunction shade) {
  const ShadingTable table(scene);
  const SphereView view = scene.spheres.view();
  std::vector<Path> paths = start(scene, seed);
  std::vector<Vec3> expected_radiance(kWavefront, Vec3{0, 0, 0});
  std::vector<Vec3> radiance(kWavefront, Vec3{0, 0, 0});
  auto w = std::make_unique<Wavefront>();
  for (int bounce = 0; bounce < 12 && !paths.empty(); ++bounce) {
    load(paths, *w);
    intersect(view, std::span(w->rays.data(), w->live), std::span(w->hits.data(), w->live));
    shade(*w, table, scene.sky, radiance.data());
    paths = reference_bounce(scene, paths, expected_radiance);
    SCOPED_TRACE("bounce " + std::to_string(bounce));
    expect_same(paths, *w);
    for (std::size_t i = 0; i < kWavefront; ++i)
      expect_same(expected_radiance[i], radiance[i], "radiance", i);
    if (testing::Test::HasFailure()) return;
  }
}

// Whether this CPU runs a copy: its instruction set is supported, and the copy is the one picked
// for that set (avx512's copy also needs AVX-512's DQ, VL and BW parts).
bool runs_here(const ShadeClone& clone) {
  const auto runs = supported_isas();
  return clone.isa == Isa::scalar ||
         (std::find(runs.begin(), runs.end(), clone.isa) != runs.end() &&
          shade_for(clone.isa) == clone.shade);
}

// Every copy of the passes the build has (one per instruction set) that runs here, whether or
// not the renderer would pick it.
void expect_every_copy_agrees(const Scene& scene, std::uint64_t seed) {
  for (const ShadeClone& clone : shade_clones()) {
    if (!runs_here(clone)) continue;
    SCOPED_TRACE("passes for " + std::string(isa_name(clone.isa)));
    expect_bounces_agree(scene, seed, clone.shade);
  }
}

TEST(Wavefront, EveryInstructionSetsCopyIsListedAndPicked) {
  const auto clones = shade_clones();
  ASSERT_FALSE(clones.empty());
  EXPECT_EQ(clones.back().isa, Isa::scalar);
  EXPECT_EQ(shade_for(Isa::scalar), clones.back().shade);
  // The best copy that runs on the queries' set: never one above it.
  for (const ShadeClone& clone : clones) {
    if (clone.isa != Isa::scalar && clone.isa != Isa::avx512) {
      EXPECT_EQ(shade_for(clone.isa), clone.shade);
    }
  }
#if defined(__x86_64__)
  ASSERT_EQ(clones.size(), 4u);
  EXPECT_EQ(clones.front().isa, Isa::avx512);
  // avx512's own copy where the CPU has all of its parts, else avx2's.
  EXPECT_TRUE(shade_for(Isa::avx512) == clones.front().shade ||
              shade_for(Isa::avx512) == shade_for(Isa::avx2));
  EXPECT_NE(shade_for(Isa::avx2), shade_for(Isa::sse4_2));
  EXPECT_NE(shade_for(Isa::avx2), clones.front().shade);
#endif
}

TEST(Wavefront, MatchesTheOnePathFunctionsOnTheCover) {
  expect_every_copy_agrees(make_preset("rtiow-final"), 1);
  expect_every_copy_agrees(make_preset("rtiow-final"), 2);
}

// Every material's corner, spheres of each in turn: a metal without fuzz (no draw), a fuzzed
// one, glass of index 1.5 and of index 1 (no draw), a Lambertian, under the graded sky.
TEST(Wavefront, MatchesTheOnePathFunctionsOnEveryMaterial) {
  Scene scene = make_preset("random:300");
  const Material kinds[] = {{MaterialKind::metal, {0.9f, 0.8f, 0.7f}, 0.0f, 1.5f},
                            {MaterialKind::dielectric, {0.5f, 0.5f, 0.5f}, 0.0f, 1.5f},
                            {MaterialKind::metal, {0.6f, 0.7f, 0.8f}, 0.3f, 1.5f},
                            {MaterialKind::dielectric, {0.5f, 0.5f, 0.5f}, 0.0f, 1.0f},
                            {MaterialKind::lambertian, {0.4f, 0.5f, 0.6f}}};
  scene.materials.clear();
  for (std::size_t i = 0; i < scene.spheres.size(); ++i)
    scene.materials.push_back(kinds[i % std::size(kinds)]);
  expect_every_copy_agrees(scene, 3);
  expect_every_copy_agrees(scene, 4);
}

// start() against PathRandom and the camera, one path at a time, behind some live lanes: every
// copy, with the lens (rtiow-final's defocus blur) and without it. The new paths' records hold
// the state the tracer set in the lanes, the counter past the camera's draws and the ray's sky
// blend. The tracer's part (wavefront.hpp): the camera lanes' pixel, sample and pixel corner,
// and the path lanes' throughput, rays left and entry.
void expect_starts_agree(const Scene& scene, StartFunction start) {
  const Camera camera(scene.camera, 160, 90);
  const std::uint64_t seed = 11;
  auto w = std::make_unique<Wavefront>();
  const std::size_t begin = 37;
  w->live = kWavefront;
  for (std::size_t k = begin; k < kWavefront; ++k) {
    w->camera.pixel[k] = 1000 + 7 * k;
    w->camera.sample[k] = static_cast<std::uint32_t>(k % 5);
    w->camera.x[k] = static_cast<float>(k % 160), w->camera.y[k] = static_cast<float>(k / 160 + 3);
    w->path.throughput_r[k] = 1.0f, w->path.throughput_g[k] = 0.5f, w->path.throughput_b[k] = 0.25f;
    w->path.rays_left[k] = static_cast<std::int32_t>(k % 50 + 1);
    w->path.slot[k] = static_cast<std::uint32_t>(3 * k);
  }
  start(*w, begin, camera, PathRandom::seed_hash(seed));
  for (std::size_t k = begin; k < kWavefront; ++k) {
    PathRandom random(seed, 1000 + 7 * k, static_cast<std::uint32_t>(k % 5));
    const float px = static_cast<float>(k % 160) + random.uniform();
    const float py = static_cast<float>(k / 160 + 3) + random.uniform();
    Ray expected = camera.ray(px, py);
    if (camera.has_defocus()) {
      const Vec3 lens = random.in_unit_disk();
      expected = camera.ray(px, py, lens.x, lens.y);
    }
    expect_same(expected.origin, w->rays[k].origin, "camera origin", k);
    expect_same(expected.dir, w->rays[k].dir, "camera direction", k);
    const PathRecord& path = w->paths[k];
    EXPECT_EQ(random.counter(), path.counter()) << "lane " << k;
    expect_same({1.0f, 0.5f, 0.25f}, {path.tr, path.tg, path.tb}, "throughput", k);
    EXPECT_EQ(static_cast<std::int32_t>(k % 50 + 1), path.rays_left) << "lane " << k;
    EXPECT_EQ(3 * k, path.slot) << "lane " << k;
    EXPECT_EQ(bits(sky_blend(expected.dir)), bits(path.sky)) << "sky blend, lane " << k;
  }
}

TEST(Wavefront, StartsPathsAsPathRandomAndTheCamera) {
  for (const ShadeClone& clone : shade_clones()) {
    if (!runs_here(clone)) continue;
    SCOPED_TRACE("passes for " + std::string(isa_name(clone.isa)));
    const Scene cover = make_preset("rtiow-final");
    ASSERT_TRUE(Camera(cover.camera, 160, 90).has_defocus());
    expect_starts_agree(cover, clone.start);
    Scene pinhole = cover;
    pinhole.camera.defocus_angle = 0.0f;
    ASSERT_FALSE(Camera(pinhole.camera, 160, 90).has_defocus());
    expect_starts_agree(pinhole, clone.start);
  }
}

}  // namespace
}  // namespace sphray::render
