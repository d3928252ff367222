// The C API (sphray.h) against the C++ API, through libsphray.so: on a million random rays, the
// same hits, occlusion, surfaces and spawned rays, bit for bit, on brute force and on the BVH.
// ctest runs this once per instruction set (SPHRAY_ISA set by tests/kernel/CMakeLists.txt), so
// every kernel the library carries is checked through the C entry points.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <sphray/sphray.h>
#include <sphray/sphray.hpp>

namespace {

// Sanitizer presets set SPHRAY_TEST_SCALE to trace a fraction of the rays (test_support.hpp).
std::size_t scaled(std::size_t n) {
  const char* text = std::getenv("SPHRAY_TEST_SCALE");
  const double s = text != nullptr ? std::atof(text) : 1.0;
  return s > 0.0 && s < 1.0 ? static_cast<std::size_t>(static_cast<double>(n) * s) : n;
}

float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

// Spheres as a caller's array of structures: the C API reads it through a stride.
struct CallerSphere {
  float x, y, z, r;
};

std::vector<CallerSphere> random_spheres(std::size_t n, std::mt19937& rng) {
  const float r_mean = 6.0f / std::cbrt(static_cast<float>(n) + 1.0f);
  std::vector<CallerSphere> spheres(n);
  for (CallerSphere& s : spheres)
    s = {uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -10, 10),
         r_mean * uniform(rng, 0.3f, 1.7f)};
  spheres[n / 2].r = -1.0f;  // never hit
  return spheres;
}

// Rays from a box around the spheres, any direction length, a few with a finite tmax or a
// positive tmin, and a few invalid ones (they must miss through both APIs).
std::vector<sphray_ray> random_rays(std::size_t n, std::mt19937& rng) {
  std::vector<sphray_ray> rays(n);
  for (std::size_t i = 0; i < n; ++i) {
    sphray_ray& r = rays[i];
    r = {uniform(rng, -12, 12),
         uniform(rng, -12, 12),
         uniform(rng, -12, 12),
         uniform(rng, -1, 1),
         uniform(rng, -1, 1),
         uniform(rng, -1, 1),
         0.0f,
         INFINITY};
    const float scale = std::exp(uniform(rng, std::log(0.1f), std::log(10.0f)));
    r.dx *= scale;
    r.dy *= scale;
    r.dz *= scale;
    if (i % 7 == 1) r.tmax = uniform(rng, 0.5f, 20.0f);
    if (i % 11 == 2) r.tmin = uniform(rng, 0.0f, 3.0f);
    if (i % 997 == 3) r.ox = NAN;
  }
  return rays;
}

sphray::Ray to_cpp(const sphray_ray& r) {
  return {{r.ox, r.oy, r.oz}, {r.dx, r.dy, r.dz}, r.tmin, r.tmax};
}

bool same_bits(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

// The scene both APIs query: the C API's copy through the stride, the C++ API's SphereSoA.
class CApiAgreement : public ::testing::TestWithParam<int> {
 protected:
  void SetUp() override {
    const char* requested = std::getenv("SPHRAY_ISA");
    if (requested != nullptr && std::string(sphray_active_isa()) != requested)
      GTEST_SKIP() << "SPHRAY_ISA=" << requested << " does not run on this machine";
    std::mt19937 rng(2026);
    const std::size_t n = GetParam() == SPHRAY_ACCEL_BVH ? 2000 : 100;
    caller_ = random_spheres(n, rng);
    for (const CallerSphere& s : caller_)
      spheres_.add({s.x, s.y, s.z}, s.r);
    if (GetParam() == SPHRAY_ACCEL_BVH) bvh_.emplace(spheres_.view());
    sphray_scene_args args = SPHRAY_SCENE_ARGS_INIT;
    args.accel = GetParam();
    ASSERT_EQ(sphray_scene_create(&caller_[0].x, &caller_[0].y, &caller_[0].z, &caller_[0].r, n,
                                  sizeof(CallerSphere), &args, &scene_),
              SPHRAY_OK)
        << sphray_last_error();
    rays_ = random_rays(scaled(1'000'000), rng);
  }
  void TearDown() override {
    if (scene_ != nullptr) {
      EXPECT_EQ(sphray_scene_release(scene_), SPHRAY_OK);
    }
  }

  sphray::Hit cpp_intersect(const sphray_ray& r) const {
    return bvh_ ? sphray::intersect(*bvh_, to_cpp(r))
                : sphray::intersect(spheres_.view(), to_cpp(r));
  }
  bool cpp_occluded(const sphray_ray& r) const {
    return bvh_ ? sphray::occluded(*bvh_, to_cpp(r)) : sphray::occluded(spheres_.view(), to_cpp(r));
  }

  std::vector<CallerSphere> caller_;
  sphray::SphereSoA spheres_;
  std::optional<sphray::SphereBVH> bvh_;
  sphray_scene* scene_ = nullptr;
  std::vector<sphray_ray> rays_;
};

TEST_P(CApiAgreement, IntersectMatchesTheCppApiAndTheScalarReference) {
  std::vector<sphray_hit> hits(rays_.size());
  ASSERT_EQ(sphray_intersect(scene_, rays_.data(), rays_.size(), hits.data(), nullptr), SPHRAY_OK);
  std::size_t found = 0;
  for (std::size_t i = 0; i < rays_.size(); ++i) {
    const sphray::Hit expected = cpp_intersect(rays_[i]);
    ASSERT_TRUE(hits[i].id == expected.id && same_bits(hits[i].t, expected.t))
        << "ray " << i << ": C " << hits[i].id << " " << hits[i].t << ", C++ " << expected.id << " "
        << expected.t;
    if (hits[i].id != SPHRAY_NO_HIT) ++found;
  }
  EXPECT_GT(found, rays_.size() / 10);  // the rays do meet spheres
  // The scalar reference, on a sample (it tests every sphere for every ray).
  for (std::size_t i = 0; i < rays_.size(); i += 50) {
    const sphray::Hit reference = sphray::scalar::intersect(spheres_.view(), to_cpp(rays_[i]));
    ASSERT_TRUE(hits[i].id == reference.id && same_bits(hits[i].t, reference.t)) << "ray " << i;
  }
}

// The arrays form gives each ray the hit the struct calls give it: with per-ray bounds, with
// NULL bounds (the defaults), and with per-ray masks (through sphray_query_args, as for
// sphray_intersect).
TEST_P(CApiAgreement, ArraysMatchTheStructCalls) {
  const std::size_t n = std::min<std::size_t>(rays_.size(), scaled(100'000));
  std::vector<float> ox, oy, oz, dx, dy, dz, tmin, tmax;
  std::vector<std::uint32_t> masks;
  std::vector<sphray_ray> unbounded;
  for (std::size_t i = 0; i < n; ++i) {
    const sphray_ray& r = rays_[i];
    ox.push_back(r.ox), oy.push_back(r.oy), oz.push_back(r.oz);
    dx.push_back(r.dx), dy.push_back(r.dy), dz.push_back(r.dz);
    tmin.push_back(r.tmin), tmax.push_back(r.tmax);
    masks.push_back(static_cast<std::uint32_t>(i % 3));  // 0: the ray sees nothing
    unbounded.push_back({r.ox, r.oy, r.oz, r.dx, r.dy, r.dz, 0.0f, INFINITY});
  }
  sphray_ray_arrays arrays{ox.data(), oy.data(), oz.data(),   dx.data(),
                           dy.data(), dz.data(), tmin.data(), tmax.data()};
  std::vector<float> t(n);
  std::vector<std::uint32_t> id(n);
  std::vector<sphray_hit> expected(n);
  const auto expect_same = [&](const char* what) {
    std::size_t found = 0;
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_TRUE(id[i] == expected[i].id && same_bits(t[i], expected[i].t))
          << what << " ray " << i << ": arrays " << id[i] << " " << t[i] << ", structs "
          << expected[i].id << " " << expected[i].t;
      found += id[i] != SPHRAY_NO_HIT;
    }
    EXPECT_GT(found, n / 20) << what;  // the rays do meet spheres
  };
  ASSERT_EQ(sphray_intersect(scene_, rays_.data(), n, expected.data(), nullptr), SPHRAY_OK);
  ASSERT_EQ(sphray_intersect_arrays(scene_, &arrays, n, t.data(), id.data(), nullptr), SPHRAY_OK)
      << sphray_last_error();
  expect_same("bounds");
  arrays.tmin = arrays.tmax = nullptr;
  ASSERT_EQ(sphray_intersect(scene_, unbounded.data(), n, expected.data(), nullptr), SPHRAY_OK);
  ASSERT_EQ(sphray_intersect_arrays(scene_, &arrays, n, t.data(), id.data(), nullptr), SPHRAY_OK);
  expect_same("no bounds");
  sphray_query_args args = SPHRAY_QUERY_ARGS_INIT;
  args.masks = masks.data();
  ASSERT_EQ(sphray_intersect(scene_, unbounded.data(), n, expected.data(), &args), SPHRAY_OK);
  ASSERT_EQ(sphray_intersect_arrays(scene_, &arrays, n, t.data(), id.data(), &args), SPHRAY_OK);
  expect_same("masks");
  for (std::size_t i = 0; i < n; i += 3)
    ASSERT_EQ(id[i], SPHRAY_NO_HIT) << "ray " << i << " of mask 0";
}

TEST_P(CApiAgreement, OccludedMatchesTheCppApi) {
  std::vector<unsigned char> occluded(rays_.size(), 7);
  ASSERT_EQ(sphray_occluded(scene_, rays_.data(), rays_.size(), occluded.data(), nullptr),
            SPHRAY_OK);
  for (std::size_t i = 0; i < rays_.size(); ++i)
    ASSERT_EQ(occluded[i], cpp_occluded(rays_[i]) ? 1 : 0) << "ray " << i;
}

// Shadow rays towards one point, 32 at a time from a short row of origins somewhere in the
// scene: coherent groups, which the tree's stream call takes in packets
// (kernel/src/bvh/packet_stream.hpp). Each answer must still be the single-ray call's; some
// rows are blocked and some not, so a wrong answer shows either way.
TEST_P(CApiAgreement, CoherentOccludedRaysMatchTheSingleRayCalls) {
  std::mt19937 rng(7);
  const float light[3] = {3.0f, 40.0f, -2.0f};
  std::vector<sphray_ray> rays;
  for (int row = 0; row < 128; ++row) {
    const float base[3] = {uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -10, 10)};
    for (int k = 0; k < 32; ++k) {
      const float o[3] = {base[0] + 0.004f * static_cast<float>(k), base[1], base[2]};
      rays.push_back({o[0], o[1], o[2], light[0] - o[0], light[1] - o[1], light[2] - o[2], 0.0f,
                      k % 5 == 0 ? 0.5f : 1.0f});
    }
  }
  std::vector<unsigned char> occluded(rays.size(), 7);
  ASSERT_EQ(sphray_occluded(scene_, rays.data(), rays.size(), occluded.data(), nullptr), SPHRAY_OK);
  std::size_t blocked = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(occluded[i], cpp_occluded(rays[i]) ? 1 : 0) << "ray " << i;
    blocked += occluded[i];
  }
  EXPECT_GT(blocked, rays.size() / 20);
  EXPECT_LT(blocked, rays.size() - rays.size() / 20);
}

// Threads through sphray_query_args (every query on every thread count: c_api_threads_test.cpp).
TEST_P(CApiAgreement, ParallelCallsMatchTheSerialOnes) {
  // A tenth of the rays: still 25 chunks of work to share.
  const std::size_t n = std::min<std::size_t>(rays_.size(), scaled(100'000));
  std::vector<sphray_hit> serial(n), parallel(n);
  ASSERT_EQ(sphray_intersect(scene_, rays_.data(), n, serial.data(), nullptr), SPHRAY_OK);
  std::vector<unsigned char> occluded(n), occluded_parallel(n);
  ASSERT_EQ(sphray_occluded(scene_, rays_.data(), n, occluded.data(), nullptr), SPHRAY_OK);
  for (unsigned threads : {0u, 1u, 3u, SPHRAY_THREADS_ALL}) {
    sphray_query_args args = SPHRAY_QUERY_ARGS_INIT;
    args.threads = threads;
    ASSERT_EQ(sphray_intersect(scene_, rays_.data(), n, parallel.data(), &args), SPHRAY_OK);
    ASSERT_EQ(std::memcmp(serial.data(), parallel.data(), n * sizeof(sphray_hit)), 0)
        << threads << " threads";
    ASSERT_EQ(sphray_occluded(scene_, rays_.data(), n, occluded_parallel.data(), &args), SPHRAY_OK);
    ASSERT_EQ(occluded, occluded_parallel) << threads << " threads";
  }
}

TEST_P(CApiAgreement, SurfaceAndSpawnMatchTheCppApi) {
  const std::size_t n = std::min<std::size_t>(rays_.size(), scaled(100'000));
  std::vector<sphray_hit> hits(n);
  std::vector<sphray_hit_surface> surfaces(n);
  ASSERT_EQ(sphray_intersect(scene_, rays_.data(), n, hits.data(), nullptr), SPHRAY_OK);
  ASSERT_EQ(sphray_surface(scene_, rays_.data(), hits.data(), n, surfaces.data()), SPHRAY_OK);
  std::vector<float> dirs(3 * n);
  std::mt19937 rng(7);
  for (float& d : dirs)
    d = uniform(rng, -1, 1);
  std::vector<sphray_ray> spawned(n);
  ASSERT_EQ(sphray_spawn(surfaces.data(), dirs.data(), n, spawned.data()), SPHRAY_OK);
  for (std::size_t i = 0; i < n; ++i) {
    const sphray::Surface s =
        sphray::surface(spheres_.view(), to_cpp(rays_[i]), {hits[i].t, hits[i].id});
    const sphray_hit_surface& c = surfaces[i];
    const float expected[9] = {s.point.x,  s.point.y, s.point.z, s.normal.x, s.normal.y,
                               s.normal.z, s.error.x, s.error.y, s.error.z};
    const float got[9] = {c.px, c.py, c.pz, c.nx, c.ny, c.nz, c.ex, c.ey, c.ez};
    for (int k = 0; k < 9; ++k)
      ASSERT_TRUE(same_bits(got[k], expected[k])) << "ray " << i << " field " << k;
    ASSERT_EQ(c.front_face, s.front_face ? 1 : 0) << "ray " << i;
    const sphray::Ray r = sphray::spawn(s, {dirs[3 * i], dirs[3 * i + 1], dirs[3 * i + 2]});
    const float expected_ray[8] = {r.origin.x, r.origin.y, r.origin.z, r.dir.x,
                                   r.dir.y,    r.dir.z,    r.tmin,     r.tmax};
    const sphray_ray& g = spawned[i];
    const float got_ray[8] = {g.ox, g.oy, g.oz, g.dx, g.dy, g.dz, g.tmin, g.tmax};
    for (int k = 0; k < 8; ++k)
      ASSERT_TRUE(same_bits(got_ray[k], expected_ray[k])) << "ray " << i << " field " << k;
  }
}

TEST_P(CApiAgreement, RefitMatchesTheCppApi) {
  // Every sphere moves and grows a little; the C++ side refits (or, brute force, re-reads).
  for (std::size_t i = 0; i < caller_.size(); ++i) {
    caller_[i].x += 0.25f;
    caller_[i].r *= 1.1f;
    spheres_.set(static_cast<std::uint32_t>(i), {caller_[i].x, caller_[i].y, caller_[i].z},
                 caller_[i].r);
  }
  if (bvh_) bvh_->refit(spheres_.view());
  ASSERT_EQ(sphray_scene_refit(scene_, &caller_[0].x, &caller_[0].y, &caller_[0].z, &caller_[0].r,
                               caller_.size(), sizeof(CallerSphere)),
            SPHRAY_OK)
      << sphray_last_error();
  const std::size_t n = std::min<std::size_t>(rays_.size(), scaled(200'000));
  std::vector<sphray_hit> hits(n);
  ASSERT_EQ(sphray_intersect(scene_, rays_.data(), n, hits.data(), nullptr), SPHRAY_OK);
  for (std::size_t i = 0; i < n; ++i) {
    const sphray::Hit expected = cpp_intersect(rays_[i]);
    ASSERT_TRUE(hits[i].id == expected.id && same_bits(hits[i].t, expected.t)) << "ray " << i;
  }
}

std::string accel_name(const ::testing::TestParamInfo<int>& info) {
  return info.param == SPHRAY_ACCEL_BVH ? "bvh" : "brute";
}

// The queries beyond the closest hit: every crossing (capped and counted), the counts, the
// nearest sphere, occupancy and overlaps, as the C++ API answers them.
TEST_P(CApiAgreement, QueriesBeyondTheClosestHitMatchTheCppApi) {
  const std::size_t n = std::min<std::size_t>(rays_.size(), 20000);
  constexpr std::size_t kSlots = 3;
  std::vector<sphray_hit> hits(n * kSlots, sphray_hit{-1.0f, 7});
  std::vector<unsigned char> exits(n * kSlots, 9);
  std::vector<size_t> counts(n), only(n);
  ASSERT_EQ(sphray_intersect_all(scene_, rays_.data(), n, kSlots, hits.data(), exits.data(),
                                 counts.data(), nullptr),
            SPHRAY_OK);
  ASSERT_EQ(sphray_count_hits(scene_, rays_.data(), n, only.data(), nullptr), SPHRAY_OK);
  std::vector<sphray_hit> nearest(n * kSlots, sphray_hit{-1.0f, 7});
  std::vector<unsigned char> nearest_exits(n * kSlots, 9);
  std::vector<size_t> written(n);
  ASSERT_EQ(sphray_intersect_nearest(scene_, rays_.data(), n, kSlots, nearest.data(),
                                     nearest_exits.data(), written.data(), nullptr),
            SPHRAY_OK);
  std::size_t crossings = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sphray::Hit want[kSlots];
    bool want_exit[kSlots];
    const sphray::Ray ray = to_cpp(rays_[i]);
    const std::size_t total = bvh_ ? sphray::intersect_all(*bvh_, ray, want, want_exit)
                                   : sphray::intersect_all(spheres_.view(), ray, want, want_exit);
    ASSERT_EQ(counts[i], total) << "ray " << i;
    ASSERT_EQ(only[i], total) << "ray " << i;
    // The nearest crossings alone: intersect_all's first slots, how many written.
    ASSERT_EQ(written[i], std::min(total, kSlots)) << "ray " << i;
    for (std::size_t k = 0; k < kSlots; ++k) {
      const std::size_t slot = i * kSlots + k;
      ASSERT_TRUE(nearest[slot].id == hits[slot].id && same_bits(nearest[slot].t, hits[slot].t))
          << "ray " << i;
      ASSERT_EQ(nearest_exits[slot], exits[slot]) << "ray " << i;
    }
    crossings += total;
    for (std::size_t k = 0; k < kSlots; ++k) {
      const sphray_hit& got = hits[i * kSlots + k];
      if (k < total) {
        ASSERT_TRUE(got.id == want[k].id && same_bits(got.t, want[k].t)) << "ray " << i;
        ASSERT_EQ(exits[i * kSlots + k], want_exit[k] ? 1 : 0) << "ray " << i;
      } else {
        ASSERT_TRUE(got.id == 7 && got.t == -1.0f) << "ray " << i << ": wrote past the total";
      }
    }
  }
  EXPECT_GT(crossings, n / 5);
  // Points: random ones in the spheres' box.
  std::mt19937 rng(7);
  std::vector<float> points(3 * n);
  for (float& x : points)
    x = uniform(rng, -11, 11);
  std::vector<sphray_nearest_sphere> near(n);
  std::vector<unsigned char> in(n);
  ASSERT_EQ(sphray_nearest(scene_, points.data(), n, 2.0f, near.data(), nullptr), SPHRAY_OK);
  ASSERT_EQ(sphray_inside(scene_, points.data(), n, in.data(), nullptr), SPHRAY_OK);
  std::size_t found = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const sphray::Vec3 p{points[3 * i], points[3 * i + 1], points[3 * i + 2]};
    const sphray::Nearest want =
        bvh_ ? sphray::nearest(*bvh_, p, 2.0f) : sphray::nearest(spheres_.view(), p, 2.0f);
    ASSERT_TRUE(near[i].id == want.id && same_bits(near[i].distance, want.distance) &&
                same_bits(near[i].px, want.point.x) && same_bits(near[i].py, want.point.y) &&
                same_bits(near[i].pz, want.point.z))
        << "point " << i;
    found += want.found();
    const bool want_in = bvh_ ? sphray::inside(*bvh_, p) : sphray::inside(spheres_.view(), p);
    ASSERT_EQ(in[i], want_in ? 1 : 0) << "point " << i;
  }
  EXPECT_GT(found, n / 10);
  for (std::size_t i = 0; i < 200; ++i) {
    const float* c = &points[3 * i];
    std::uint32_t got[4] = {0, 0, 0, 0};
    std::uint32_t want[4] = {0, 0, 0, 0};
    size_t total = 0;
    ASSERT_EQ(sphray_overlapping(scene_, c, 1.5f, 4, got, &total), SPHRAY_OK);
    const sphray::Vec3 p{c[0], c[1], c[2]};
    const std::size_t want_total = bvh_ ? sphray::overlapping(*bvh_, p, 1.5f, want)
                                        : sphray::overlapping(spheres_.view(), p, 1.5f, want);
    ASSERT_EQ(total, want_total);
    ASSERT_TRUE(std::equal(got, got + 4, want)) << "ball " << i;
  }
}

// Masks through the C API: sphere masks set through a stride (a caller's structure), one mask
// per ray, against the C++ API given the same masks; then refit keeps them and NULL clears them.
TEST_P(CApiAgreement, MaskedQueriesMatchTheCppApi) {
  struct CallerMask {
    std::uint32_t mask;
    float weight;  // another field of the caller's structure, skipped by the stride
  };
  std::mt19937 rng(11);
  std::vector<CallerMask> sphere_masks(caller_.size());
  for (std::size_t i = 0; i < caller_.size(); ++i) {
    sphere_masks[i] = {1u << (rng() % 3), 1.0f};
    spheres_.set_mask(static_cast<std::uint32_t>(i), sphere_masks[i].mask);
  }
  if (bvh_) bvh_->refit(spheres_.view());
  ASSERT_EQ(sphray_scene_set_masks(scene_, &sphere_masks[0].mask, sizeof(CallerMask)), SPHRAY_OK)
      << sphray_last_error();
  const std::size_t n = std::min<std::size_t>(rays_.size(), scaled(100'000));
  std::vector<std::uint32_t> ray_masks(n);
  for (std::uint32_t& m : ray_masks)
    m = rng() % 8;  // 0 (sees nothing) to every one of the three bits
  auto cpp_ray = [&](std::size_t i) {
    sphray::Ray ray = to_cpp(rays_[i]);
    ray.mask = ray_masks[i];
    return ray;
  };
  std::vector<sphray_hit> hits(n);
  std::vector<unsigned char> occluded(n);
  std::vector<size_t> counts(n), all_counts(n);
  constexpr std::size_t kSlots = 2;
  std::vector<sphray_hit> all(n * kSlots);
  sphray_query_args masked = SPHRAY_QUERY_ARGS_INIT;
  masked.masks = ray_masks.data();
  ASSERT_EQ(sphray_intersect(scene_, rays_.data(), n, hits.data(), &masked), SPHRAY_OK);
  ASSERT_EQ(sphray_occluded(scene_, rays_.data(), n, occluded.data(), &masked), SPHRAY_OK);
  ASSERT_EQ(sphray_count_hits(scene_, rays_.data(), n, counts.data(), &masked), SPHRAY_OK);
  ASSERT_EQ(sphray_intersect_all(scene_, rays_.data(), n, kSlots, all.data(), nullptr,
                                 all_counts.data(), &masked),
            SPHRAY_OK);
  std::vector<sphray_hit> nearest(n * kSlots);
  std::vector<size_t> written(n);
  ASSERT_EQ(sphray_intersect_nearest(scene_, rays_.data(), n, kSlots, nearest.data(), nullptr,
                                     written.data(), &masked),
            SPHRAY_OK);
  // The arrays form takes the same masks from the same args: sphray_intersect's hits.
  std::vector<float> ox(n), oy(n), oz(n), dx(n), dy(n), dz(n), tmin(n), tmax(n), t(n);
  std::vector<std::uint32_t> id(n);
  for (std::size_t i = 0; i < n; ++i) {
    const sphray_ray& r = rays_[i];
    ox[i] = r.ox, oy[i] = r.oy, oz[i] = r.oz, dx[i] = r.dx, dy[i] = r.dy, dz[i] = r.dz;
    tmin[i] = r.tmin, tmax[i] = r.tmax;
  }
  const sphray_ray_arrays arrays{ox.data(), oy.data(), oz.data(),   dx.data(),
                                 dy.data(), dz.data(), tmin.data(), tmax.data()};
  ASSERT_EQ(sphray_intersect_arrays(scene_, &arrays, n, t.data(), id.data(), &masked), SPHRAY_OK);
  std::size_t hidden = 0;  // rays whose closest hit the masks changed
  for (std::size_t i = 0; i < n; ++i) {
    const sphray::Ray ray = cpp_ray(i);
    const sphray::Hit want =
        bvh_ ? sphray::intersect(*bvh_, ray) : sphray::intersect(spheres_.view(), ray);
    ASSERT_TRUE(hits[i].id == want.id && same_bits(hits[i].t, want.t)) << "ray " << i;
    ASSERT_TRUE(id[i] == want.id && same_bits(t[i], want.t)) << "arrays, ray " << i;
    if (want.found()) {
      ASSERT_TRUE(all[i * kSlots].id == want.id && same_bits(all[i * kSlots].t, want.t))
          << "ray " << i;
    }
    const bool want_occluded =
        bvh_ ? sphray::occluded(*bvh_, ray) : sphray::occluded(spheres_.view(), ray);
    ASSERT_EQ(occluded[i], want_occluded ? 1 : 0) << "ray " << i;
    const std::size_t want_count =
        bvh_ ? sphray::count_hits(*bvh_, ray) : sphray::count_hits(spheres_.view(), ray);
    ASSERT_EQ(counts[i], want_count) << "ray " << i;
    ASSERT_EQ(all_counts[i], want_count) << "ray " << i;
    ASSERT_EQ(written[i], std::min(want_count, kSlots)) << "ray " << i;
    for (std::size_t k = 0; k < written[i]; ++k) {
      const std::size_t slot = i * kSlots + k;
      ASSERT_TRUE(nearest[slot].id == all[slot].id && same_bits(nearest[slot].t, all[slot].t))
          << "ray " << i;
    }
    if (want.id != cpp_intersect(rays_[i]).id) ++hidden;
    if (ray_masks[i] == 0) {
      ASSERT_EQ(hits[i].id, SPHRAY_NO_HIT) << "ray " << i;
    }
  }
  EXPECT_GT(hidden, n / 20);  // the masks do hide spheres

  // A refit keeps the masks: the same masked answers after moving nothing.
  ASSERT_EQ(sphray_scene_refit(scene_, &caller_[0].x, &caller_[0].y, &caller_[0].z, &caller_[0].r,
                               caller_.size(), sizeof(CallerSphere)),
            SPHRAY_OK);
  std::vector<sphray_hit> again(n);
  ASSERT_EQ(sphray_intersect(scene_, rays_.data(), n, again.data(), &masked), SPHRAY_OK);
  for (std::size_t i = 0; i < n; ++i)
    ASSERT_TRUE(again[i].id == hits[i].id && same_bits(again[i].t, hits[i].t)) << "ray " << i;

  // NULL masks: every sphere seen again, by every ray but those of mask 0.
  ASSERT_EQ(sphray_scene_set_masks(scene_, nullptr, 0), SPHRAY_OK);
  ASSERT_EQ(sphray_intersect(scene_, rays_.data(), n, again.data(), &masked), SPHRAY_OK);
  for (std::size_t i = 0; i < n; ++i) {
    const sphray::Hit want =
        ray_masks[i] == 0 ? sphray::Hit{rays_[i].tmax, SPHRAY_NO_HIT} : cpp_intersect(rays_[i]);
    ASSERT_TRUE(again[i].id == want.id) << "ray " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Accel, CApiAgreement,
                         ::testing::Values(SPHRAY_ACCEL_BRUTE, SPHRAY_ACCEL_BVH), accel_name);

TEST(CApiInfo, NamesTheActiveIsaAndTheVersion) {
  EXPECT_EQ(std::string(sphray_active_isa()), std::string(sphray::isa_name(sphray::active_isa())));
  for (const std::size_t n :
       {std::size_t{0}, std::size_t{512}, std::size_t{2048}, std::size_t{1} << 20})
    EXPECT_EQ(std::string(sphray_bvh_isa(n)), std::string(sphray::isa_name(sphray::bvh_isa(n))))
        << n;
  EXPECT_EQ(std::string(sphray_version()), std::string(sphray::kVersion));
  // The number orders as the three parts do, and the string spells the same three.
  EXPECT_EQ(sphray_version_number(), SPHRAY_VERSION_NUMBER);
  EXPECT_EQ(sphray_version_number(),
            sphray::kVersionMajor * 10000 + sphray::kVersionMinor * 100 + sphray::kVersionPatch);
  EXPECT_EQ(std::string(sphray_version()), std::to_string(SPHRAY_VERSION_MAJOR) + "." +
                                               std::to_string(SPHRAY_VERSION_MINOR) + "." +
                                               std::to_string(SPHRAY_VERSION_PATCH));
}

TEST(CApiInfo, AutoAnswersLikeTheReferenceEitherSideOfTheCrossover) {
  // Which structure AUTO picks is not observable through the results (both give the same
  // hits): the answers either side of the crossover (128 spheres) must both be right.
  for (std::size_t n : {std::size_t{127}, std::size_t{128}}) {
    std::mt19937 rng(static_cast<unsigned>(n));
    const std::vector<CallerSphere> caller = random_spheres(n, rng);
    sphray::SphereSoA spheres;
    for (const CallerSphere& s : caller)
      spheres.add({s.x, s.y, s.z}, s.r);
    sphray_scene* scene = nullptr;
    ASSERT_EQ(sphray_scene_create(&caller[0].x, &caller[0].y, &caller[0].z, &caller[0].r, n,
                                  sizeof(CallerSphere), nullptr, &scene),
              SPHRAY_OK);
    std::size_t size = 0;
    ASSERT_EQ(sphray_scene_size(scene, &size), SPHRAY_OK);
    EXPECT_EQ(size, n);
    const std::vector<sphray_ray> rays = random_rays(scaled(20'000), rng);
    std::vector<sphray_hit> hits(rays.size());
    ASSERT_EQ(sphray_intersect(scene, rays.data(), rays.size(), hits.data(), nullptr), SPHRAY_OK);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const sphray::Hit expected = sphray::scalar::intersect(spheres.view(), to_cpp(rays[i]));
      ASSERT_TRUE(hits[i].id == expected.id && same_bits(hits[i].t, expected.t)) << "ray " << i;
    }
    EXPECT_EQ(sphray_scene_release(scene), SPHRAY_OK);
  }
}

// The SPHRAY_ISA_ values and the names sphray_active_isa() and sphray_bvh_isa() give them.
struct IsaValue {
  int value;
  const char* name;
};
constexpr IsaValue kIsaValues[] = {{SPHRAY_ISA_SCALAR, "scalar"},
                                   {SPHRAY_ISA_SSE4_2, "sse4.2"},
                                   {SPHRAY_ISA_AVX2, "avx2"},
                                   {SPHRAY_ISA_AVX512, "avx512"},
                                   {SPHRAY_ISA_NEON, "neon"}};

// The SPHRAY_ISA_ value of a name, or -1 (which no instruction set is).
int isa_value(const std::string& name) {
  for (const IsaValue& isa : kIsaValues)
    if (name == isa.name) return isa.value;
  return -1;
}

// sphray_isa_supported says yes to exactly the sets the C++ API lists as built and runnable,
// to AUTO, and to the set the queries run on; no to values that name no set.
TEST(CApiInfo, IsaSupportedIsTheCppApisList) {
  EXPECT_EQ(sphray_isa_supported(SPHRAY_ISA_AUTO), 1);
  EXPECT_EQ(sphray_isa_supported(SPHRAY_ISA_SCALAR), 1);
  for (const IsaValue& isa : kIsaValues) {
    const std::optional<sphray::Isa> cpp = sphray::parse_isa(isa.name);
    ASSERT_TRUE(cpp.has_value()) << isa.name;
    const std::span<const sphray::Isa> runnable = sphray::supported_isas();
    const bool runs = std::find(runnable.begin(), runnable.end(), *cpp) != runnable.end();
    EXPECT_EQ(sphray_isa_supported(isa.value), runs ? 1 : 0) << isa.name;
  }
  EXPECT_EQ(sphray_isa_supported(isa_value(sphray_active_isa())), 1) << sphray_active_isa();
  for (int unknown : {-1, 6, 99})
    EXPECT_EQ(sphray_isa_supported(unknown), 0) << unknown;
}

// sphray_scene_isa of a scene built with the defaults: the set sphray_bvh_isa(count) names for a
// tree, the one sphray_active_isa() names for brute force.
TEST(CApiInfo, SceneIsaOfTheDefaultScenes) {
  std::mt19937 rng(5);
  for (const auto& [n, accel] : {std::pair<std::size_t, int>{5, SPHRAY_ACCEL_AUTO},
                                 {1000, SPHRAY_ACCEL_AUTO},
                                 {1000, SPHRAY_ACCEL_BRUTE},
                                 {5, SPHRAY_ACCEL_BVH}}) {
    SCOPED_TRACE(std::to_string(n) + " spheres, accel " + std::to_string(accel));
    const std::vector<CallerSphere> caller = random_spheres(n, rng);
    sphray_scene_args args = SPHRAY_SCENE_ARGS_INIT;
    args.accel = accel;
    sphray_scene* scene = nullptr;
    ASSERT_EQ(sphray_scene_create(&caller[0].x, &caller[0].y, &caller[0].z, &caller[0].r, n,
                                  sizeof(CallerSphere),
                                  accel == SPHRAY_ACCEL_AUTO ? nullptr : &args, &scene),
              SPHRAY_OK)
        << sphray_last_error();
    const bool tree = accel == SPHRAY_ACCEL_BVH || (accel == SPHRAY_ACCEL_AUTO && n >= 128);
    const std::string expected = tree ? sphray_bvh_isa(n) : sphray_active_isa();
    int isa = -7;
    ASSERT_EQ(sphray_scene_isa(scene, &isa), SPHRAY_OK) << sphray_last_error();
    EXPECT_EQ(isa, isa_value(expected)) << "expected " << expected;
    EXPECT_EQ(sphray_scene_release(scene), SPHRAY_OK);
  }
}

// A scene given an instruction set is laid out for it and queried with it, whatever SPHRAY_ISA
// says (ctest runs this under each), and answers as the default scene does, bit for bit:
// closest hits, occlusion, every crossing. Many spheres (a tree either way) and a few (a flat
// tree with a chosen set, brute force by default), through AUTO and BVH.
TEST(CApiInfo, AChosenIsaGivesTheDefaultScenesBits) {
  std::mt19937 rng(17);
  for (const std::size_t n : {std::size_t{1000}, std::size_t{5}}) {
    const std::vector<CallerSphere> caller = random_spheres(n, rng);
    const std::vector<sphray_ray> rays = random_rays(scaled(20'000), rng);
    const std::size_t count = rays.size();
    constexpr std::size_t kSlots = 4;
    struct Answers {
      std::vector<sphray_hit> hits, all;
      std::vector<unsigned char> occluded, exits;
      std::vector<size_t> counts;
    };
    // Every output starts as the same pattern, so that a slot written by one scene and left by
    // the other shows.
    const auto answer = [&](const sphray_scene_args* args, Answers& out) {
      sphray_scene* scene = nullptr;
      ASSERT_EQ(sphray_scene_create(&caller[0].x, &caller[0].y, &caller[0].z, &caller[0].r, n,
                                    sizeof(CallerSphere), args, &scene),
                SPHRAY_OK)
          << sphray_last_error();
      out.hits.assign(count, sphray_hit{-1.0f, 7});
      out.all.assign(count * kSlots, sphray_hit{-1.0f, 7});
      out.occluded.assign(count, 9);
      out.exits.assign(count * kSlots, 9);
      out.counts.assign(count, 99);
      EXPECT_EQ(sphray_intersect(scene, rays.data(), count, out.hits.data(), nullptr), SPHRAY_OK);
      EXPECT_EQ(sphray_occluded(scene, rays.data(), count, out.occluded.data(), nullptr),
                SPHRAY_OK);
      EXPECT_EQ(sphray_intersect_all(scene, rays.data(), count, kSlots, out.all.data(),
                                     out.exits.data(), out.counts.data(), nullptr),
                SPHRAY_OK);
      if (args != nullptr) {
        int isa = -7;
        EXPECT_EQ(sphray_scene_isa(scene, &isa), SPHRAY_OK);
        EXPECT_EQ(isa, args->isa) << "the scene's instruction set";
      }
      EXPECT_EQ(sphray_scene_release(scene), SPHRAY_OK);
    };
    Answers want;
    answer(nullptr, want);
    if (HasFatalFailure()) return;
    const std::size_t found = static_cast<std::size_t>(
        std::count_if(want.hits.begin(), want.hits.end(),
                      [](const sphray_hit& h) { return h.id != SPHRAY_NO_HIT; }));
    EXPECT_GT(found, count / 20) << n << " spheres: the rays do meet spheres";
    for (const IsaValue& isa : kIsaValues) {
      if (sphray_isa_supported(isa.value) != 1) continue;
      for (const int accel : {SPHRAY_ACCEL_AUTO, SPHRAY_ACCEL_BVH}) {
        SCOPED_TRACE(std::to_string(n) + " spheres, isa " + isa.name + ", accel " +
                     std::to_string(accel));
        sphray_scene_args args = SPHRAY_SCENE_ARGS_INIT;
        args.accel = accel;
        args.isa = isa.value;
        Answers got;
        answer(&args, got);
        if (HasFatalFailure()) return;
        EXPECT_EQ(std::memcmp(got.hits.data(), want.hits.data(), count * sizeof(sphray_hit)), 0);
        EXPECT_EQ(got.occluded, want.occluded);
        EXPECT_EQ(std::memcmp(got.all.data(), want.all.data(), count * kSlots * sizeof(sphray_hit)),
                  0);
        EXPECT_EQ(got.exits, want.exits);
        EXPECT_EQ(got.counts, want.counts);
      }
    }
  }
}

}  // namespace
