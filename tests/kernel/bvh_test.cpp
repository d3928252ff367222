// SphereBVH against brute force: random scenes of every kind from 0 to 10^5 spheres, each
// instruction set's tree against the same instruction set's brute-force kernel on large random
// ray sets; refit against rebuild; the build's independence from the thread count.
#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <iostream>
#include <stdexcept>

#include "test_support.hpp"

namespace sphray {
namespace {

using test::uniform;

enum class Kind { uniform, clustered, nested, huge_and_tiny, identical, one_point };

const char* kind_name(Kind k) {
  constexpr const char* names[] = {"uniform",       "clustered", "nested",
                                   "huge_and_tiny", "identical", "one_point"};
  return names[static_cast<int>(k)];
}

constexpr Kind kKinds[] = {Kind::uniform,       Kind::clustered, Kind::nested,
                           Kind::huge_and_tiny, Kind::identical, Kind::one_point};

float log_uniform(std::mt19937& rng, float lo, float hi) {
  return std::exp(uniform(rng, std::log(lo), std::log(hi)));
}

// n spheres of one kind in about [-50, 50]^3, about 1 in 16 of them invalid (zero, negative,
// NaN or infinite fields), which the tree must never report and must not let widen its boxes.
test::LooseSpheres make_scene(Kind kind, std::size_t n, std::mt19937& rng) {
  test::LooseSpheres s(n % 3);
  const float r_uniform = 50.0f / std::cbrt(static_cast<float>(std::max<std::size_t>(n, 1)));
  std::vector<Vec3> clusters(8);
  for (auto& c : clusters)
    c = test::random_in_box(rng, 45.0f);
  const Vec3 point = test::random_in_box(rng, 10.0f);
  const float same_r = uniform(rng, 0.5f, 5.0f);
  for (std::size_t i = 0; i < n; ++i) {
    switch (kind) {
      case Kind::uniform:
        s.add(test::random_in_box(rng, 50.0f), r_uniform * uniform(rng, 0.5f, 1.5f));
        break;
      case Kind::clustered:
        s.add(clusters[rng() % clusters.size()] + test::random_in_box(rng, 2.0f),
              log_uniform(rng, 0.01f, 0.5f));
        break;
      case Kind::nested:  // shells around a few centres, radii spread over 5 decades
        s.add(clusters[rng() % 3], log_uniform(rng, 1e-3f, 60.0f));
        break;
      case Kind::huge_and_tiny:
        s.add(test::random_in_box(rng, 50.0f),
              rng() % 64 == 0 ? log_uniform(rng, 1e2f, 1e4f) : log_uniform(rng, 1e-4f, 1.0f));
        break;
      case Kind::identical:
        s.add(point, same_r);
        break;
      case Kind::one_point:
        s.add(point, log_uniform(rng, 1e-3f, 20.0f));
        break;
    }
  }
  const float bad[] = {0.0f, -1.0f, NAN, INFINITY, -INFINITY};
  for (std::size_t i = 0; i < n; ++i)
    if (rng() % 16 == 0) s.storage[rng() % 4][s.offset + i] = bad[rng() % 5];
  return s;
}

// Rays of every sort the contract names: from anywhere in and around the scene in any
// direction, aimed at a sphere, with finite and negative bounds, axis-parallel (zero direction
// components) from exactly on a box plane of the tree, and the invalid ones.
std::vector<Ray> make_rays(std::size_t count, const SphereView& v, const SphereBVH& bvh,
                           std::mt19937& rng) {
  std::vector<Ray> rays(count);
  const detail::BvhData& d = detail::BvhAccess::data(bvh);
  for (auto& ray : rays) {
    ray = Ray{test::random_in_box(rng, 60.0f), test::random_direction(rng)};
    switch (rng() % 8) {
      case 0:  // aimed at a sphere's centre (often a hit, and ties among identical spheres)
        if (v.count != 0) {
          const std::size_t i = rng() % v.count;
          const Vec3 c{v.cx[i], v.cy[i], v.cz[i]};
          if (isfinite(c) && c != ray.origin) ray.dir = c - ray.origin;
        }
        break;
      case 1:
        ray.tmin = uniform(rng, -20.0f, 20.0f);
        ray.tmax = ray.tmin + log_uniform(rng, 1e-3f, 100.0f);
        break;
      case 2: {  // parallel to an axis, the origin on a plane of a node's box
        const int axis = static_cast<int>(rng() % 3);
        float* o[] = {&ray.origin.x, &ray.origin.y, &ray.origin.z};
        float* dir[] = {&ray.dir.x, &ray.dir.y, &ray.dir.z};
        // Zero, or so small (subnormal) that its inverse is still infinite.
        const float tiny[] = {0.0f, -0.0f, 0x1p-140f, -0x1p-140f};
        *dir[axis] = tiny[rng() % 4];
        if (d.node_count != 0) {
          const float* node = d.nodes + (rng() % d.node_count) * detail::kBvhNodeRows * d.width;
          const float plane = node[(2 * axis + rng() % 2) * d.width + rng() % d.width];
          if (std::isfinite(plane)) *o[axis] = plane;
        }
        if (length_squared(ray.dir) < 1e-6f) ray.dir = {0.0f, 0.0f, 1.0f};
        break;
      }
      case 3: {
        const Ray invalid[] = {{{0, 0, 0}, {NAN, 1, 0}},      {{0, 0, 0}, {0, 0, 0}},
                               {{INFINITY, 0, 0}, {1, 0, 0}}, {{0, 0, 0}, {1, 0, 0}, 2.0f, 1.0f},
                               {{0, 0, 0}, {1, 0, 0}, NAN},   {{0, 0, 0}, {1e-30f, 0, 0}}};
        if (rng() % 8 == 0) ray = invalid[rng() % 6];
        break;
      }
      default:
        break;
    }
  }
  return rays;
}

struct Tally {
  std::size_t rays = 0;
};

// The tree built for k's instruction set against k's brute force on every ray: the same id and
// the same t bit for bit (both run the same sphere math), and the same occlusion.
void compare(const EntryTable& k, const SphereView& v, const SphereBVH& bvh,
             const std::vector<Ray>& rays, Tally& tally, const std::string& what) {
  std::vector<Hit> streamed(rays.size());
  intersect(bvh, rays, streamed);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Ray& ray = rays[i];
    const Hit want = k.intersect(v, ray);
    const Hit got = intersect(bvh, ray);
    ASSERT_EQ(got.id, want.id) << what << " ray " << i << ": got t " << got.t << ", brute force t "
                               << want.t;
    ASSERT_EQ(std::bit_cast<std::uint32_t>(got.t), std::bit_cast<std::uint32_t>(want.t))
        << what << " ray " << i << ": t " << got.t << " vs " << want.t;
    ASSERT_EQ(streamed[i].id, got.id) << what << " stream, ray " << i;
    ASSERT_EQ(occluded(bvh, ray), k.occluded(v, ray)) << what << " occluded, ray " << i;
  }
  tally.rays += rays.size();
}

std::string label(const EntryTable& k, Kind kind, std::size_t n) {
  return std::string(isa_name(k.isa)) + " " + kind_name(kind) + " n=" + std::to_string(n);
}

// Rays per scene: brute force over n spheres is the expensive side, so fewer rays on larger
// scenes, but never fewer than 2000.
std::size_t ray_count(const EntryTable& k, std::size_t n) {
  const double budget = k.isa == Isa::scalar ? 2e7 : 1e8;
  return test::scaled(
      std::clamp<std::size_t>(static_cast<std::size_t>(budget / double(n + 1)), 2000, 20000));
}

class BvhAgreement : public ::testing::TestWithParam<Isa> {};

TEST_P(BvhAgreement, MatchesBruteForceOnEveryKindAndSize) {
  const EntryTable* k = find_entries(GetParam());
  if (k == nullptr) GTEST_SKIP() << "this machine cannot run " << isa_name(GetParam());
  std::mt19937 rng(5);
  Tally tally;
  std::size_t branch_free_trees = 0, branching_trees = 0;  // the two leaf tests
  const std::size_t largest = k->isa == Isa::scalar ? 10000 : 100000;
  for (Kind kind : kKinds) {
    // 33 to 200 straddle the small-tree limit on every width (a tree of at most 8 leaves is
    // read as brute force, QueryPlan::brute_force_tree): both sides must give brute force's bits.
    for (std::size_t n : {0u, 1u, 3u, 4u, 5u, 8u, 9u, 16u, 17u, 33u, 64u, 100u, 128u, 160u, 200u,
                          1000u, 10000u, 100000u}) {
      if (n > largest) continue;
      const test::LooseSpheres scene = make_scene(kind, n, rng);
      const SphereBVH bvh(scene.view(), k->isa);
      ASSERT_EQ(bvh.size(), n);
      ASSERT_EQ(bvh.isa(), k->isa);
      const auto rays = make_rays(ray_count(*k, n), scene.view(), bvh, rng);
      compare(*k, scene.view(), bvh, rays, tally, label(*k, kind, n));
      if (n > 100)
        ++(detail::BvhAccess::data(bvh).leaf_overlap >= detail::kBvhBranchFreeOverlap
               ? branch_free_trees
               : branching_trees);
    }
  }
  std::cout << "[ compared ] " << tally.rays << " rays on " << isa_name(k->isa) << ", "
            << branch_free_trees << " trees over 100 spheres with the branch-free leaf test, "
            << branching_trees << " with the branching one\n";
  EXPECT_GE(tally.rays, test::scaled(1000000) * 99 / 100);
  if (k->isa != Isa::scalar) {  // the scalar traversal has one leaf test
    EXPECT_GT(branch_free_trees, 0u);
    EXPECT_GT(branching_trees, 0u);
  }
}

std::string isa_param_name(const ::testing::TestParamInfo<Isa>& info) {
  return info.param == Isa::sse4_2 ? std::string("sse4_2") : std::string(isa_name(info.param));
}

#if defined(__aarch64__)
INSTANTIATE_TEST_SUITE_P(EveryIsa, BvhAgreement, ::testing::Values(Isa::scalar, Isa::neon),
                         isa_param_name);
#else
INSTANTIATE_TEST_SUITE_P(EveryIsa, BvhAgreement,
                         ::testing::Values(Isa::scalar, Isa::sse4_2, Isa::avx2, Isa::avx512),
                         isa_param_name);
#endif

// Moves every sphere (and turns some invalid, some valid again), then compares the refitted
// tree with a tree built on the moved spheres and with brute force.
TEST(Bvh, RefitThenQueryEqualsRebuildThenQuery) {
  std::mt19937 rng(7);
  for (const EntryTable* k : test::runnable_kernels()) {
    for (std::size_t n : {1u, 9u, 1000u, 30000u}) {
      test::LooseSpheres scene = make_scene(Kind::uniform, n, rng);
      SphereBVH refitted(scene.view(), k->isa);
      const test::LooseSpheres moved = make_scene(Kind::clustered, n, rng);
      scene = moved;
      refitted.refit(scene.view());
      const SphereBVH rebuilt(scene.view(), k->isa);
      const auto rays = make_rays(ray_count(*k, n) / 2, scene.view(), rebuilt, rng);
      Tally tally;
      compare(*k, scene.view(), refitted, rays, tally, "refit " + label(*k, Kind::clustered, n));
      for (const Ray& ray : rays) {
        const Hit a = intersect(refitted, ray), b = intersect(rebuilt, ray);
        ASSERT_EQ(a.id, b.id);
        ASSERT_EQ(std::bit_cast<std::uint32_t>(a.t), std::bit_cast<std::uint32_t>(b.t));
      }
    }
  }
}

// The tree's limit, 2^31 spheres (docs/bvh.md), is refused before a sphere is read or a byte is
// allocated: the view's arrays here do not exist.
TEST(Bvh, MoreThan2To31SpheresAreRefusedBeforeAnyWork) {
  const sphray::SphereView huge{nullptr, nullptr, nullptr, nullptr, (std::size_t{1} << 31) + 1};
  try {
    const sphray::SphereBVH tree(huge);
    ADD_FAILURE() << "built a tree of 2^31 + 1 spheres";
  } catch (const std::length_error& e) {
    EXPECT_NE(std::string(e.what()).find("2^31"), std::string::npos) << e.what();
  }
}

TEST(Bvh, RefitRejectsAnotherCount) {
  std::mt19937 rng(8);
  const test::LooseSpheres scene = make_scene(Kind::uniform, 100, rng);
  SphereBVH bvh(scene.view());
  const test::LooseSpheres other = make_scene(Kind::uniform, 99, rng);
  EXPECT_THROW(bvh.refit(other.view()), std::invalid_argument);
}

bool same_tree(const SphereBVH& a, const SphereBVH& b) {
  const detail::BvhData &x = detail::BvhAccess::data(a), &y = detail::BvhAccess::data(b);
  if (x.node_count != y.node_count || x.width != y.width || x.spheres.count != y.spheres.count)
    return false;
  return std::memcmp(x.nodes, y.nodes,
                     x.node_count * detail::kBvhNodeRows * x.width * sizeof(float)) == 0 &&
         std::memcmp(x.ids, y.ids, x.spheres.count * sizeof(std::uint32_t)) == 0;
}

TEST(Bvh, BuildIsTheSameWhateverTheThreadCount) {
  std::mt19937 rng(9);
  for (Kind kind : {Kind::uniform, Kind::clustered, Kind::identical}) {
    // parallel_min 1024 splits the work across threads from 1024 spheres on, so that even the
    // sanitizer runs, which scale the workload down, build in parallel at every level.
    const std::size_t n = std::max<std::size_t>(test::scaled(100000), 8000);
    const test::LooseSpheres scene = make_scene(kind, n, rng);
    const SphereBVH one(scene.view(), BvhBuildOptions{1, 1024});
    for (unsigned threads : {2u, 3u, 0u}) {
      const SphereBVH many(scene.view(), BvhBuildOptions{threads, 1024});
      EXPECT_TRUE(same_tree(one, many)) << kind_name(kind) << ", " << threads << " threads";
    }
    // The default work split builds a tree that answers the same.
    const SphereBVH standard(scene.view());
    const auto rays = make_rays(2000, scene.view(), standard, rng);
    for (const Ray& ray : rays) {
      const Hit a = intersect(one, ray), b = intersect(standard, ray);
      ASSERT_EQ(a.id, b.id) << kind_name(kind);
      ASSERT_EQ(a.t, b.t) << kind_name(kind);
    }
  }
}

// A tree of millions of spheres writes its slots in stretches of 2^16 leaves, giving back the
// pages of the build's records as it goes (build.cpp, write_leaves), after binning its top
// levels from samples: every sphere is in exactly one slot, with its own centre and radius, and
// every other slot is never-hit padding.
TEST(Bvh, EverySphereOfAMillionsTreeIsInItsSlot) {
  std::mt19937 rng(13);
  constexpr std::size_t kCount = 2000000;
  const std::size_t n = std::max<std::size_t>(test::scaled(kCount), 20000);
  test::LooseSpheres scene;
  for (std::size_t i = 0; i < n; ++i)
    scene.add(test::random_in_box(rng, 100.0f), uniform(rng, 0.1f, 0.4f));
  const SphereBVH bvh(scene.view());
  const detail::BvhData& d = detail::BvhAccess::data(bvh);
  const SphereView v = scene.view();
  std::vector<std::uint8_t> seen(n, 0);
  std::size_t wrong = 0, padding = 0;
  for (std::size_t i = 0; i < d.spheres.count; ++i) {
    const std::uint32_t id = d.ids[i];
    if (id == kNoHit) {
      padding += d.spheres.radius[i] == 0.0f ? 1 : 0;
      continue;
    }
    ASSERT_LT(id, n);
    ++seen[id];
    wrong += d.spheres.cx[i] != v.cx[id] || d.spheres.cy[i] != v.cy[id] ||
             d.spheres.cz[i] != v.cz[id] || d.spheres.radius[i] != v.radius[id];
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<std::ptrdiff_t>(n));
  EXPECT_EQ(padding, d.spheres.count - n);  // every slot without a sphere is padding
  if (n == kCount) {                        // more leaves than one stretch
    EXPECT_GT(d.spheres.count / d.width, std::size_t{1} << 16);
  }
}

// The progress function sees fractions from 0 to 1 ending at 1, changes nothing in the tree,
// and stops the build when it says so or throws; the next build is unaffected.
TEST(Bvh, ProgressReportsAndCancelsTheBuild) {
  std::mt19937 rng(10);
  const std::size_t n = std::max<std::size_t>(test::scaled(100000), 8000);
  const test::LooseSpheres scene = make_scene(Kind::uniform, n, rng);
  const SphereBVH plain(scene.view(), BvhBuildOptions{0, 1024});

  std::atomic<int> calls{0};
  std::atomic<bool> in_range{true};
  std::atomic<double> last{-1.0};
  const BuildProgress watch = [&](double done) {
    ++calls;
    if (!(done >= 0.0 && done <= 1.0)) in_range = false;
    last = done;
    return true;
  };
  const SphereBVH seen(scene.view(), BvhBuildOptions{0, 1024}, watch);
  EXPECT_TRUE(same_tree(plain, seen));
  EXPECT_GT(calls.load(), 4);
  EXPECT_TRUE(in_range.load());
  EXPECT_EQ(last.load(), 1.0);  // the last call, after the build

  std::atomic<int> asked{0};
  const BuildProgress stop = [&](double) { return ++asked < 3; };
  EXPECT_THROW(SphereBVH(scene.view(), BvhBuildOptions{0, 1024}, stop), BuildCancelled);
  EXPECT_GE(asked.load(), 3);

  struct Mine {};
  const BuildProgress throws = [](double) -> bool { throw Mine{}; };
  EXPECT_THROW(SphereBVH(scene.view(), BvhBuildOptions{0, 1024}, throws), Mine);

  EXPECT_TRUE(same_tree(plain, SphereBVH(scene.view(), BvhBuildOptions{0, 1024})));
}

// The stream may walk scattered rays in turns on a tree larger than the caches (over 4 MB:
// 200000 spheres take about 5 MB), with the tree's leaf test, and coherent ones one by one:
// either way each ray gets exactly, to the bit, what the single-ray query gives it. Rays of
// every sort are mixed in, including ones the walk in turns hands back to the single-ray path.
// Two scenes, one for each leaf test (see kBvhBranchFreeOverlap).
TEST(Bvh, StreamGivesEachRayExactlyTheSingleRayHit) {
  std::mt19937 rng(12);
  for (Kind kind : {Kind::uniform, Kind::clustered}) {
    const test::LooseSpheres scene = make_scene(kind, 200000, rng);
    for (const EntryTable* k : test::runnable_kernels()) {
      const SphereBVH bvh(scene.view(), k->isa);
      if (k->isa != Isa::scalar) {
        ASSERT_GT(bvh.memory_bytes(), std::size_t{4} << 20) << "too small for the walk in turns";
        ASSERT_EQ(detail::BvhAccess::data(bvh).leaf_overlap >= detail::kBvhBranchFreeOverlap,
                  kind == Kind::uniform)
            << "overlap " << detail::BvhAccess::data(bvh).leaf_overlap;
      }
      std::vector<Ray> rays = make_rays(test::scaled(3000), scene.view(), bvh, rng);
      const Vec3 eye{0.0f, 0.0f, -150.0f};
      for (int i = 0; i < 1500; ++i)  // a camera's rays, all within a narrow cone
        rays.push_back({eye, {uniform(rng, -0.3f, 0.3f), uniform(rng, -0.3f, 0.3f), 1.0f}});
      for (int i = 0; i < 2500; ++i)  // scattered, all ahead of their origin
        rays.push_back({test::random_in_box(rng, 50.0f), test::random_direction(rng)});
      std::vector<Hit> streamed(rays.size());
      intersect(bvh, rays, streamed);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit single = intersect(bvh, rays[i]);
        ASSERT_EQ(streamed[i].id, single.id) << test::name_of(k) << " ray " << i;
        ASSERT_EQ(std::bit_cast<std::uint32_t>(streamed[i].t),
                  std::bit_cast<std::uint32_t>(single.t))
            << test::name_of(k) << " ray " << i << ": " << streamed[i].t << " vs " << single.t;
      }
    }
  }
}

// The measure that picks the leaf test: the leaf boxes' summed volume over the root box's.
TEST(Bvh, LeafOverlapIsTheLeafBoxesVolumeOverTheRootBox) {
  for (const EntryTable* k : test::runnable_kernels()) {
    const std::size_t w = k->bvh_width;
    // One leaf: its box is the root box.
    test::LooseSpheres few;
    for (std::size_t i = 0; i < w; ++i)
      few.add({float(i), 0.0f, 0.0f}, 0.5f);
    EXPECT_FLOAT_EQ(detail::BvhAccess::data(SphereBVH(few.view(), k->isa)).leaf_overlap, 1.0f)
        << test::name_of(k);
    // 4w equal spheres: four full leaves, each box the root box.
    test::LooseSpheres same;
    for (std::size_t i = 0; i < 4 * w; ++i)
      same.add({1.0f, 2.0f, 3.0f}, 2.0f);
    SphereBVH bvh(same.view(), k->isa);
    EXPECT_FLOAT_EQ(detail::BvhAccess::data(bvh).leaf_overlap, 4.0f) << test::name_of(k);
    // Refit to spheres far apart on a line: the leaves' boxes become thin slices of the root
    // box, and the overlap drops below the branch-free threshold.
    test::LooseSpheres apart;
    for (std::size_t i = 0; i < 4 * w; ++i)
      apart.add({100.0f * float(i), 0.0f, 0.0f}, 1.0f);
    bvh.refit(apart.view());
    EXPECT_LT(detail::BvhAccess::data(bvh).leaf_overlap, detail::kBvhBranchFreeOverlap)
        << test::name_of(k);
    EXPECT_GT(detail::BvhAccess::data(bvh).leaf_overlap, 0.0f) << test::name_of(k);
  }
}

TEST(Bvh, KeepsItsOwnCopyOfTheSpheres) {
  std::mt19937 rng(10);
  auto scene = std::make_unique<test::LooseSpheres>(make_scene(Kind::uniform, 500, rng));
  const SphereBVH bvh(scene->view());
  const auto rays = make_rays(2000, scene->view(), bvh, rng);
  std::vector<Hit> before(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i)
    before[i] = intersect(scene->view(), rays[i]);
  scene.reset();
  for (std::size_t i = 0; i < rays.size(); ++i)
    ASSERT_EQ(intersect(bvh, rays[i]).id, before[i].id);
}

TEST(Bvh, EmptyTreesMissAndStreamsCheckTheirSize) {
  const SphereBVH empty;
  const Ray ray{{0, 0, 0}, {1, 0, 0}, 0.0f, 5.0f};
  const Hit hit = intersect(empty, ray);
  EXPECT_FALSE(hit.found());
  EXPECT_EQ(hit.t, 5.0f);
  EXPECT_FALSE(occluded(empty, ray));
  std::vector<Ray> rays(2, ray);
  std::vector<Hit> hits(1);
  EXPECT_THROW(intersect(empty, rays, hits), std::length_error);
}

TEST(Bvh, MemoryStaysUnderFortyBytesPerSphere) {
  std::mt19937 rng(11);
  const test::LooseSpheres scene = make_scene(Kind::uniform, 100000, rng);
  for (const EntryTable* k : test::runnable_kernels()) {
    const SphereBVH bvh(scene.view(), k->isa);
    const double per_sphere = double(bvh.memory_bytes()) / double(bvh.size());
    std::cout << "[ memory   ] " << isa_name(k->isa) << ": " << per_sphere << " bytes per sphere\n";
    EXPECT_GE(per_sphere, 20.0);  // at least the sphere copy and its id
    EXPECT_LE(per_sphere, 40.0) << isa_name(k->isa);
  }
}

}  // namespace
}  // namespace sphray
