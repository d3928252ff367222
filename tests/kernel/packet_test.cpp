// The stream calls' packets (bvh/packet.hpp): intersect(bvh, rays, hits) and
// occluded(bvh, rays, blocked) must give each ray exactly, to the bit, what the single-ray
// calls give it, whether its group went through the tree as a packet or one ray at a time.
// The oracle is the single-ray walk, itself checked against brute force (bvh_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "dispatch/query_plan.hpp"
#include "test_support.hpp"

namespace sphray {
namespace {

// Scenes of n spheres in a box of half-size 10: random, in a tight cluster, one sphere many
// times over (every hit a tie, which the lower id wins), and random with a ground sphere.
enum class Scene { random, clustered, ties, ground };

SphereSoA make_scene(Scene kind, std::size_t n, std::mt19937& rng, bool masked,
                     Vec3 offset = {0, 0, 0}) {
  SphereSoA s;
  if (kind == Scene::ground) s.add(Vec3{0.0f, -1000.0f, 0.0f} + offset, 990.0f);
  for (std::size_t i = 0; i < n; ++i) {
    // Radii that let about half the camera's rays hit something (test::fill_random's).
    const float r_mean = 6.0f / std::cbrt(static_cast<float>(n) + 1.0f);
    Vec3 c = test::random_in_box(rng, 10.0f);
    float r = r_mean * test::uniform(rng, 0.3f, 1.7f);
    if (kind == Scene::clustered) c = c * 0.2f;
    if (kind == Scene::ties) c = Vec3{float(i % 5), 0.0f, 0.0f}, r = 2.0f;
    if (masked)
      s.add(c + offset, r, 1u << (i % 3));
    else
      s.add(c + offset, r);
  }
  return s;
}

// A pinhole camera's rays of a width x height image, row-major, as a renderer makes them.
std::vector<Ray> camera_rays(Vec3 eye, Vec3 at, int width, int height, float tmin) {
  const Vec3 forward = normalize(at - eye);
  const Vec3 right = normalize(cross(forward, Vec3{0, 1, 0}));
  const Vec3 up = cross(right, forward);
  std::vector<Ray> rays;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const float u = (static_cast<float>(x) + 0.5f) / static_cast<float>(width) - 0.5f;
      const float v = 0.5f - (static_cast<float>(y) + 0.5f) / static_cast<float>(height);
      rays.push_back({eye, forward + 0.5f * u * right + 0.4f * v * up, tmin});
    }
  }
  return rays;
}

// Shadow rays towards one point light from where the rays hit, in the rays' order: tmax 1 is
// the light itself (dir = light - p).
std::vector<Ray> shadow_rays(const SphereBVH& bvh, const std::vector<Ray>& rays, Vec3 light) {
  std::vector<Ray> shadows;
  for (const Ray& ray : rays) {
    const Hit hit = intersect(bvh, ray);
    if (!hit.found()) continue;
    const Vec3 p = ray.at(hit.t);
    shadows.push_back({p, light - p, 1e-3f, 1.0f});
  }
  return shadows;
}

// rays with every seventh one replaced by a ray the contract or the packets treat apart:
// invalid (missing everything), not ahead of its origin (the general box test), of another
// octant, masked out, or with a short or unbounded interval. Their groups go on as packets of
// the others.
std::vector<Ray> with_odd_rays(std::vector<Ray> rays) {
  const Vec3 o = rays.front().origin, d = rays.front().dir;
  const Ray odd[] = {
      {o, {NAN, d.y, d.z}},
      {{INFINITY, o.y, o.z}, d},
      {o, {0.0f, 0.0f, 0.0f}},
      {o, d, 2.0f, 1.0f},
      {o, d, NAN},
      {o, {0.0f, d.y, d.z}},
      {o, {0x1p-140f, d.y, d.z}},
      {o, d, -5.0f},
      {o, -1.0f * d},
      {o, {-d.x, d.y, d.z}},
      {o, d, 0.0f, INFINITY, 0u},
      {o, d, 0.0f, 30.0f},
      {o, d, 0.0f, NAN},
      {o, {d.x * 1e-20f, d.y * 1e-20f, d.z * 1e-20f}},
  };
  for (std::size_t i = 3, k = 0; i < rays.size(); i += 7, ++k)
    rays[i] = odd[k % std::size(odd)];
  return rays;
}

// Random origins and directions: no group is coherent, every ray walks alone.
std::vector<Ray> scattered_rays(std::size_t n, std::mt19937& rng) {
  std::vector<Ray> rays(n);
  for (auto& r : rays)
    r = {test::random_in_box(rng, 12.0f), test::random_direction(rng)};
  return rays;
}

void expect_stream_is_single(const SphereBVH& bvh, const std::vector<Ray>& rays,
                             const std::string& what, bool must_hit = true) {
  std::vector<Hit> hits(rays.size());
  intersect(bvh, rays, hits);
  // std::vector<bool> has no span: a plain array.
  std::unique_ptr<bool[]> blocked(new bool[rays.size()]);
  occluded(bvh, rays, std::span<bool>(blocked.get(), rays.size()));
  std::size_t found = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit single = intersect(bvh, rays[i]);
    ASSERT_EQ(hits[i].id, single.id) << what << " ray " << i;
    ASSERT_EQ(std::bit_cast<std::uint32_t>(hits[i].t), std::bit_cast<std::uint32_t>(single.t))
        << what << " ray " << i << ": " << hits[i].t << " vs " << single.t;
    ASSERT_EQ(blocked[i], occluded(bvh, rays[i])) << what << " occluded, ray " << i;
    found += single.found();
  }
  // The rays must reach the spheres for the comparison to say anything.
  if (must_hit) {
    EXPECT_GT(found, 0u) << what;
  }
}

std::string label(const EntryTable* k, Scene scene, std::size_t n, bool masked) {
  const char* names[] = {"random", "clustered", "ties", "ground"};
  return test::name_of(k) + " " + names[static_cast<int>(scene)] + " n=" + std::to_string(n) +
         (masked ? " masked" : "");
}

// Camera rays (in both halves of the image: two octants), shadow rays towards a point light,
// the same with odd rays mixed in, scattered rays, and a stream whose length leaves a partial
// packet: on every instruction set, both leaf tests, masked spheres and ties.
TEST(Packets, StreamGivesEachRayExactlyTheSingleRayAnswer) {
  std::mt19937 rng(19);
  for (const EntryTable* k : test::runnable_kernels()) {
    for (const Scene kind : {Scene::random, Scene::clustered, Scene::ties, Scene::ground}) {
      for (const std::size_t n : {std::size_t{40}, std::size_t{3000}}) {
        for (const bool masked : {false, true}) {
          const SphereSoA scene = make_scene(kind, n, rng, masked);
          const SphereBVH bvh(scene.view(), k->isa);
          const std::string what = label(k, kind, n, masked);
          std::vector<Ray> camera = camera_rays({1.0f, 4.0f, -40.0f}, {0, 0, 0}, 83, 61, 0.0f);
          if (masked)
            for (std::size_t i = 0; i < camera.size(); ++i)
              camera[i].mask = 1u << (i / 200 % 3);
          expect_stream_is_single(bvh, camera, what + " camera");
          if (kind != Scene::ties) {  // a hit point on one of many equal spheres: no shadow
            expect_stream_is_single(bvh, shadow_rays(bvh, camera, {30.0f, 40.0f, -20.0f}),
                                    what + " shadow");
          }
          expect_stream_is_single(bvh, with_odd_rays(camera), what + " odd");
          // Three packets and five rays, from the middle of the image (where the spheres are).
          const auto middle = camera.begin() + static_cast<std::ptrdiff_t>(camera.size() / 2);
          expect_stream_is_single(bvh, {middle, middle + 101}, what + " partial");
          if (kind == Scene::random)
            expect_stream_is_single(bvh, scattered_rays(2000, rng), what + " scattered");
        }
      }
    }
  }
}

// A camera inside a dense scene, its rays starting past tmin = 1e-3 as bounce rays do: every
// packet meets many leaves, the branch-free leaf test among them.
TEST(Packets, DenseSceneFromInside) {
  std::mt19937 rng(20);
  SphereSoA scene;
  for (int i = 0; i < 20000; ++i)
    scene.add(test::random_in_box(rng, 10.0f), test::uniform(rng, 0.05f, 0.3f));
  for (const EntryTable* k : test::runnable_kernels()) {
    const SphereBVH bvh(scene.view(), k->isa);
    const auto camera = camera_rays({0.1f, 0.2f, 0.3f}, {5, 3, 9}, 64, 48, 1e-3f);
    expect_stream_is_single(bvh, camera, test::name_of(k) + " inside");
    expect_stream_is_single(bvh, shadow_rays(bvh, camera, {-3.0f, 9.0f, 2.0f}),
                            test::name_of(k) + " inside, shadow");
  }
}

// Shadow rays towards a directional light (one direction for all) from where the rays hit, a
// little off the surface, in the rays' order: their origins lie at every depth, so groups of
// consecutive rays are not coherent, and the stream sorts them by their lines
// (bvh/line_packet.hpp).
std::vector<Ray> sun_rays(const SphereBVH& bvh, const std::vector<Ray>& rays, Vec3 sun) {
  std::vector<Ray> shadows;
  for (const Ray& ray : rays) {
    const Hit hit = intersect(bvh, ray);
    if (hit.found()) shadows.push_back({ray.at(hit.t), sun, 1e-3f});
  }
  return shadows;
}

// Line packets (bvh/line_packet.hpp) on every instruction set: the sun's shadow rays in
// several octants (one nearly along an axis), in scenes near and far from the coordinates'
// origin (where the margin and the slide's rounding are larger), with odd rays mixed in
// (NaN, masked, other octants, not ahead), a stream whose length leaves partial packets and
// one too short for a packet, and reversed (another order for the sort).
TEST(Packets, SunShadowRaysFromScatteredOriginsGiveTheSingleRayAnswer) {
  std::mt19937 rng(22);
  const Vec3 suns[] = {normalize(Vec3{0.6f, 1.0f, 0.45f}), normalize(Vec3{-0.3f, 0.8f, -0.9f}),
                       normalize(Vec3{1e-3f, 1.0f, -2e-3f})};
  for (const EntryTable* k : test::runnable_kernels()) {
    for (const Scene kind : {Scene::random, Scene::clustered, Scene::ground}) {
      for (const bool masked : {false, true}) {
        for (const Vec3 offset : {Vec3{0, 0, 0}, Vec3{3000.0f, -20000.0f, 700.0f}}) {
          const SphereSoA scene = make_scene(kind, 3000, rng, masked, offset);
          const SphereBVH bvh(scene.view(), k->isa);
          const std::string what = label(k, kind, 3000, masked) + (offset.y != 0 ? " far" : "");
          std::vector<Ray> camera =
              camera_rays(Vec3{1.0f, 4.0f, -40.0f} + offset, offset, 83, 61, 0.0f);
          for (const Vec3 sun : suns) {
            std::vector<Ray> shadows = sun_rays(bvh, camera, sun);
            ASSERT_GT(shadows.size(), 300u) << what;
            expect_stream_is_single(bvh, shadows, what + " sun");
            expect_stream_is_single(bvh, with_odd_rays(shadows), what + " sun, odd");
            const auto partial = static_cast<std::ptrdiff_t>(shadows.size() * 2 / 3 + 5);
            expect_stream_is_single(bvh, {shadows.begin(), shadows.begin() + partial},
                                    what + " sun, partial");
            expect_stream_is_single(bvh, {shadows.begin() + 200, shadows.begin() + 240},
                                    what + " sun, short", false);
            expect_stream_is_single(bvh, {shadows.rbegin(), shadows.rend()},
                                    what + " sun, reversed");
          }
        }
      }
    }
  }
}

// The packets' leaf test with the rays in the lanes (LeafTest::any_hit_across, where
// QueryPlan::leaf_across sends a leaf's rays) on every instruction set: the sun's shadow rays
// with masks that hide a sphere from some rays of a packet and not from others, ends (tmax)
// that stop some rays short of, inside or just past a sphere, and starts (tmin) that skip
// some, in scenes whose full leaves the packets reach with many rays at once.
TEST(Packets, SunShadowRaysWithMasksAndEndsGiveTheSingleRayAnswer) {
  std::mt19937 rng(24);
  const Vec3 sun = normalize(Vec3{0.6f, 1.0f, 0.45f});
  for (const EntryTable* k : test::runnable_kernels()) {
    for (const Scene kind : {Scene::random, Scene::clustered, Scene::ground}) {
      const SphereSoA scene = make_scene(kind, 3000, rng, true);
      const SphereBVH bvh(scene.view(), k->isa);
      const std::string what = label(k, kind, 3000, true) + " sun, masks and ends";
      std::vector<Ray> shadows =
          sun_rays(bvh, camera_rays({1.0f, 4.0f, -40.0f}, {0, 0, 0}, 97, 71, 0.0f), sun);
      ASSERT_GT(shadows.size(), 300u) << what;
      for (std::size_t i = 0; i < shadows.size(); ++i) {
        shadows[i].mask = i % 4 == 3 ? 0xffffffffu : 1u << (i % 3);
        if (i % 5 == 1) shadows[i].tmax = test::uniform(rng, 0.2f, 4.0f);
        if (i % 5 == 2) shadows[i].tmin = test::uniform(rng, 0.01f, 2.0f);
      }
      expect_stream_is_single(bvh, shadows, what);
      std::size_t blocked = 0;
      for (const Ray& ray : shadows)
        blocked += occluded(bvh, ray);
      // Both answers must be common for the comparison to say anything.
      EXPECT_GT(blocked, shadows.size() / 10) << what;
      EXPECT_LT(blocked, shadows.size() * 9 / 10) << what;
    }
  }
}

// The sun's shadow rays above are what the plan sends to line packets; camera rays (which
// consecutive packets take) and scattered rays are not.
TEST(Packets, SunShadowRaysAreLinesForThePlan) {
  using Plan = detail::baseline::QueryPlan;
  std::mt19937 rng(23);
  const SphereSoA scene = make_scene(Scene::random, 3000, rng, false);
  const SphereBVH bvh(scene.view());
  const auto camera = camera_rays({1.0f, 4.0f, -40.0f}, {0, 0, 0}, 83, 61, 0.0f);
  const auto shadows = sun_rays(bvh, camera, normalize(Vec3{0.6f, 1.0f, 0.45f}));
  const auto scattered = scattered_rays(camera.size(), rng);
  const std::size_t n = Plan::kStreamChunk;
  ASSERT_GE(shadows.size(), n);
  std::vector<std::uint16_t> all(n);
  for (std::size_t i = 0; i < n; ++i)
    all[i] = static_cast<std::uint16_t>(i);
  // Consecutive groups of shadow rays are not coherent; of camera rays they are.
  std::size_t coherent = 0;
  for (std::size_t begin = 0; begin < n; begin += Plan::kPacketRays)
    coherent += Plan::coherent(&shadows[begin], Plan::kPacketRays, 20.0f);
  EXPECT_LT(coherent, n / Plan::kPacketRays / 4);
  EXPECT_TRUE(Plan::lines(shadows.data(), all.data(), n));
  EXPECT_TRUE(Plan::lines(with_odd_rays(shadows).data(), all.data(), n));
  EXPECT_FALSE(Plan::lines(camera.data(), all.data(), n));  // directions spread past 14 degrees
  EXPECT_FALSE(Plan::lines(scattered.data(), all.data(), n));
  EXPECT_FALSE(Plan::lines(shadows.data(), all.data(), Plan::kPacketRays - 1));
}

// The camera rays above go through the tree as packets: most groups of kPacketRays
// consecutive rays are coherent by the plan's measure, and scattered rays are not.
TEST(Packets, CameraRowsAreCoherentForThePlan) {
  using Plan = detail::baseline::QueryPlan;
  std::mt19937 rng(21);
  const auto camera = camera_rays({1.0f, 4.0f, -40.0f}, {0, 0, 0}, 83, 61, 0.0f);
  const auto scattered = scattered_rays(camera.size(), rng);
  std::size_t groups = 0, coherent = 0, scattered_coherent = 0;
  for (std::size_t begin = 0; begin + Plan::kPacketRays <= camera.size();
       begin += Plan::kPacketRays, ++groups) {
    coherent += Plan::coherent(&camera[begin], Plan::kPacketRays, 20.0f);
    scattered_coherent += Plan::coherent(&scattered[begin], Plan::kPacketRays, 20.0f);
  }
  EXPECT_GT(coherent, groups / 2) << coherent << " of " << groups;
  EXPECT_EQ(scattered_coherent, 0u);
}

// rays as arrays per quantity (RayArrays), and the arrays they point into.
struct RayColumnsOf {
  std::vector<float> ox, oy, oz, dx, dy, dz, tmin, tmax;
  std::vector<std::uint32_t> mask;
  RayArrays arrays;

  // with_bounds false: tmin, tmax and mask left null, for rays that have Ray's defaults.
  RayColumnsOf(const std::vector<Ray>& rays, bool with_bounds) {
    for (const Ray& r : rays) {
      ox.push_back(r.origin.x), oy.push_back(r.origin.y), oz.push_back(r.origin.z);
      dx.push_back(r.dir.x), dy.push_back(r.dir.y), dz.push_back(r.dir.z);
      tmin.push_back(r.tmin), tmax.push_back(r.tmax), mask.push_back(r.mask);
    }
    arrays = {ox.data(),
              oy.data(),
              oz.data(),
              dx.data(),
              dy.data(),
              dz.data(),
              with_bounds ? tmin.data() : nullptr,
              with_bounds ? tmax.data() : nullptr,
              with_bounds ? mask.data() : nullptr,
              rays.size()};
  }
};

// hits as arrays must hold, bit for bit, the single-ray call's hit of each ray.
void expect_hits(const std::vector<float>& t, const std::vector<std::uint32_t>& id,
                 const std::vector<Hit>& expected, const std::string& what) {
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_EQ(id[i], expected[i].id) << what << " ray " << i;
    ASSERT_EQ(std::bit_cast<std::uint32_t>(t[i]), std::bit_cast<std::uint32_t>(expected[i].t))
        << what << " ray " << i << ": " << t[i] << " vs " << expected[i].t;
  }
}

// The stream calls that take rays and hits as arrays per quantity: for camera rays (packets),
// the same with odd rays mixed in (each ray's own tmin, tmax and mask), scattered rays (alone),
// a stream cut short of a packet, small trees (built flat) and brute force, on every
// instruction set, each ray's hit is the single-ray call's, bit for bit.
TEST(Packets, ArraysOfRaysGiveEachRayTheSingleRayAnswer) {
  std::mt19937 rng(23);
  for (const EntryTable* k : test::runnable_kernels()) {
    for (const std::size_t n : {std::size_t{1}, std::size_t{40}, std::size_t{3000}}) {
      for (const bool masked : {false, true}) {
        const SphereSoA scene = make_scene(Scene::random, n, rng, masked);
        const SphereBVH bvh(scene.view(), k->isa);
        const std::string what = label(k, Scene::random, n, masked);
        const std::vector<Ray> camera = camera_rays({1.0f, 4.0f, -40.0f}, {0, 0, 0}, 83, 61, 0.0f);
        const std::vector<Ray> partial(camera.begin() + 2000, camera.begin() + 2101);
        const struct {
          const char* name;
          std::vector<Ray> rays;
          bool with_bounds;
        } cases[] = {{"camera", camera, false},
                     {"camera with bounds", camera, true},
                     {"odd", with_odd_rays(camera), true},
                     {"scattered", scattered_rays(2000, rng), false},
                     {"partial", partial, false}};
        std::size_t found = 0;
        for (const auto& c : cases) {
          const RayColumnsOf columns(c.rays, c.with_bounds);
          std::vector<float> t(c.rays.size(), -1.0f);
          std::vector<std::uint32_t> id(c.rays.size(), 7u);
          const HitArrays hits{t.data(), id.data(), c.rays.size()};
          std::vector<Hit> tree_single, brute_single;
          for (const Ray& ray : c.rays) {
            tree_single.push_back(intersect(bvh, ray));
            brute_single.push_back(k->intersect(scene.view(), ray));
            found += tree_single.back().found();
          }
          intersect(bvh, columns.arrays, hits);
          expect_hits(t, id, tree_single, what + " tree " + c.name);
          std::fill(t.begin(), t.end(), -1.0f);
          k->intersect_arrays(scene.view(), columns.arrays, hits);
          expect_hits(t, id, brute_single, what + " brute force " + c.name);
        }
        EXPECT_GT(found, 0u) << what;  // else the comparisons say little
      }
    }
  }
}

TEST(Packets, ArraysOfRaysAreChecked) {
  SphereSoA scene;
  scene.add({0, 0, 5}, 1.0f);
  const SphereBVH bvh(scene.view());
  const RayColumnsOf columns({{{0, 0, 0}, {0, 0, 1}}, {{0, 0, 0}, {0, 1, 0}}}, false);
  float t[2] = {0, 0};
  std::uint32_t id[2] = {0, 0};
  EXPECT_THROW(intersect(bvh, columns.arrays, HitArrays{t, id, 1}), std::length_error);
  EXPECT_THROW(intersect(scene.view(), columns.arrays, HitArrays{t, id, 1}), std::length_error);
  EXPECT_THROW(intersect(bvh, columns.arrays, HitArrays{t, nullptr, 2}), std::invalid_argument);
  RayArrays no_dir = columns.arrays;
  no_dir.dy = nullptr;
  EXPECT_THROW(intersect(scene.view(), no_dir, HitArrays{t, id, 2}), std::invalid_argument);
  // No rays: null arrays are fine, and nothing is written.
  intersect(bvh, RayArrays{}, HitArrays{});
  intersect(scene.view(), RayArrays{}, HitArrays{});
  intersect(bvh, columns.arrays, HitArrays{t, id, 2});
  EXPECT_EQ(id[0], 0u);
  EXPECT_EQ(t[0], 4.0f);
  EXPECT_EQ(id[1], kNoHit);
  EXPECT_EQ(t[1], INFINITY);
}

TEST(Packets, OccludedStreamChecksItsSize) {
  SphereSoA scene;
  scene.add({0, 0, 5}, 1.0f);
  const SphereBVH bvh(scene.view());
  const Ray rays[2] = {{{0, 0, 0}, {0, 0, 1}}, {{0, 0, 0}, {0, 1, 0}}};
  bool blocked[2] = {false, true};
  EXPECT_THROW(occluded(bvh, rays, std::span<bool>(blocked, 1)), std::length_error);
  occluded(bvh, rays, blocked);
  EXPECT_TRUE(blocked[0]);
  EXPECT_FALSE(blocked[1]);
}

}  // namespace
}  // namespace sphray
