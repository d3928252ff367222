// The C API in double (sphray.h, "Double precision"), through libsphray.so: a double scene's
// _d queries against the C++ API's double scalar reference, bit for bit, on brute force and on
// trees (ctest runs the agreement once per instruction set, as for float); a millimetre sphere
// 100 km out that the float calls cannot resolve; and a scene's precision kept apart, every
// call of the other precision refused with SPHRAY_ERROR_PRECISION.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <sphray/sphray.h>
#include <sphray/sphray.hpp>

#include "double_support.hpp"

namespace {

using namespace sphray;
using namespace sphray::test::doubles;

// A double scene made through the C API from the view's arrays, released at the end.
class CScene {
 public:
  CScene(const SphereViewd& v, int accel, int isa = SPHRAY_ISA_AUTO) {
    sphray_scene_args args = SPHRAY_SCENE_ARGS_INIT;
    args.accel = accel;
    args.isa = isa;
    status_ = sphray_scene_create_d(v.cx, v.cy, v.cz, v.radius, v.count, 0, &args, &scene_);
  }
  ~CScene() {
    if (scene_ != nullptr) sphray_scene_release(scene_);
  }
  CScene(const CScene&) = delete;
  CScene& operator=(const CScene&) = delete;
  int status() const { return status_; }
  sphray_scene* get() const { return scene_; }

 private:
  sphray_scene* scene_ = nullptr;
  int status_;
};

sphray_ray_d to_c(const Rayd& r) {
  return {r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax};
}

bool same(const sphray_hit_d& c, const Hitd& want) {
  return c.id == want.id &&
         std::bit_cast<std::uint64_t>(c.t) == std::bit_cast<std::uint64_t>(want.t);
}

bool same(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

// Every _d query on scene against the scalar reference over v: closest hit, occlusion, every
// crossing and the nearest 3, the crossings' count, the surfaces and the rays spawned from them.
void expect_agreement(const CScene& scene, const SphereViewd& v, const std::vector<Rayd>& rays,
                      const std::vector<std::uint32_t>& masks, const std::string& what) {
  const std::size_t n = rays.size();
  std::vector<sphray_ray_d> c_rays(n);
  std::transform(rays.begin(), rays.end(), c_rays.begin(), [](const Rayd& r) { return to_c(r); });
  sphray_query_args args = SPHRAY_QUERY_ARGS_INIT;
  args.masks = masks.empty() ? nullptr : masks.data();
  args.threads = 2;
  std::vector<sphray_hit_d> hits(n);
  std::vector<unsigned char> blocked(n);
  std::vector<std::size_t> counts(n), nearest_counts(n);
  constexpr std::size_t kSlots = 8, kNearest = 3;
  std::vector<sphray_hit_d> all(n * kSlots), nearest(n * kNearest);
  std::vector<unsigned char> exits(n * kSlots);
  ASSERT_EQ(sphray_intersect_d(scene.get(), c_rays.data(), n, hits.data(), &args), SPHRAY_OK);
  ASSERT_EQ(sphray_occluded_d(scene.get(), c_rays.data(), n, blocked.data(), &args), SPHRAY_OK);
  ASSERT_EQ(sphray_intersect_all_d(scene.get(), c_rays.data(), n, kSlots, all.data(), exits.data(),
                                   counts.data(), &args),
            SPHRAY_OK);
  ASSERT_EQ(sphray_intersect_nearest_d(scene.get(), c_rays.data(), n, kNearest, nearest.data(),
                                       nullptr, nearest_counts.data(), &args),
            SPHRAY_OK);
  std::vector<std::size_t> totals(n);
  ASSERT_EQ(sphray_count_hits_d(scene.get(), c_rays.data(), n, totals.data(), &args), SPHRAY_OK);
  // The same rays as one array per quantity.
  std::vector<double> columns[8];
  for (std::vector<double>& column : columns)
    column.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const sphray_ray_d& r = c_rays[i];
    const double values[8] = {r.ox, r.oy, r.oz, r.dx, r.dy, r.dz, r.tmin, r.tmax};
    for (std::size_t k = 0; k < 8; ++k)
      columns[k][i] = values[k];
  }
  const sphray_ray_arrays_d arrays{columns[0].data(), columns[1].data(), columns[2].data(),
                                   columns[3].data(), columns[4].data(), columns[5].data(),
                                   columns[6].data(), columns[7].data()};
  std::vector<double> array_t(n);
  std::vector<std::uint32_t> array_id(n);
  ASSERT_EQ(
      sphray_intersect_arrays_d(scene.get(), &arrays, n, array_t.data(), array_id.data(), &args),
      SPHRAY_OK)
      << sphray_last_error();
  std::vector<sphray_hit_surface_d> surfaces(n);
  ASSERT_EQ(sphray_surface_d(scene.get(), c_rays.data(), hits.data(), n, surfaces.data()),
            SPHRAY_OK);
  std::vector<double> dirs(3 * n);
  for (std::size_t i = 0; i < n; ++i)
    dirs[3 * i] = surfaces[i].nx, dirs[3 * i + 1] = surfaces[i].ny,
             dirs[3 * i + 2] = surfaces[i].nz;
  std::vector<sphray_ray_d> spawned(n);
  ASSERT_EQ(sphray_spawn_d(surfaces.data(), dirs.data(), n, spawned.data()), SPHRAY_OK);

  std::size_t found = 0;
  for (std::size_t i = 0; i < n; ++i) {
    Rayd ray = rays[i];
    if (!masks.empty()) ray.mask = masks[i];
    const Hitd want = scalar::intersect(v, ray);
    found += want.found() ? 1 : 0;
    ASSERT_TRUE(same(hits[i], want)) << what << ", ray " << i << ": want " << describe(want);
    ASSERT_TRUE(same(sphray_hit_d{array_t[i], array_id[i]}, want))
        << what << ", arrays, ray " << i << ": want " << describe(want);
    ASSERT_EQ(blocked[i] != 0, scalar::occluded(v, ray)) << what << ", ray " << i;
    std::vector<Hitd> slots(kSlots);
    bool flags[kSlots];
    const std::size_t total = scalar::intersect_all(v, ray, slots, std::span<bool>(flags, kSlots));
    ASSERT_EQ(counts[i], total) << what << ", ray " << i;
    ASSERT_EQ(totals[i], total) << what << ", ray " << i;
    ASSERT_EQ(nearest_counts[i], std::min(total, kNearest)) << what << ", ray " << i;
    for (std::size_t k = 0; k < std::min(total, kSlots); ++k) {
      ASSERT_TRUE(same(all[i * kSlots + k], slots[k])) << what << ", ray " << i << ", slot " << k;
      ASSERT_EQ(exits[i * kSlots + k] != 0, flags[k]) << what << ", ray " << i << ", slot " << k;
      if (k < kNearest) {
        ASSERT_TRUE(same(nearest[i * kNearest + k], slots[k])) << what << ", ray " << i;
      }
    }
    const Surfaced s = surface(v, ray, want);
    const sphray_hit_surface_d& c = surfaces[i];
    ASSERT_TRUE(same(c.px, s.point.x) && same(c.py, s.point.y) && same(c.pz, s.point.z) &&
                same(c.nx, s.normal.x) && same(c.ny, s.normal.y) && same(c.nz, s.normal.z) &&
                same(c.ex, s.error.x) && same(c.ey, s.error.y) && same(c.ez, s.error.z) &&
                (c.front_face != 0) == s.front_face)
        << what << ", ray " << i;
    const Rayd next = spawn(s, s.normal);
    ASSERT_TRUE(same(spawned[i].ox, next.origin.x) && same(spawned[i].oy, next.origin.y) &&
                same(spawned[i].oz, next.origin.z) && same(spawned[i].dx, next.dir.x) &&
                same(spawned[i].tmax, next.tmax))
        << what << ", ray " << i;
  }
  EXPECT_GT(found, 0u) << what;
  EXPECT_LT(found, n) << what;
}

// The point queries on scene against the scalar reference over v: the nearest sphere within
// max_distance, occupancy, and the ids a ball overlaps.
void expect_point_agreement(const CScene& scene, const SphereViewd& v,
                            const std::vector<Vec3d>& points, double max_distance,
                            const std::string& what) {
  const std::size_t n = points.size();
  std::vector<double> coordinates;
  for (const Vec3d& p : points)
    coordinates.insert(coordinates.end(), {p.x, p.y, p.z});
  sphray_query_args args = SPHRAY_QUERY_ARGS_INIT;
  args.threads = 2;
  std::vector<sphray_nearest_sphere_d> nearest(n);
  std::vector<unsigned char> inside(n);
  ASSERT_EQ(
      sphray_nearest_d(scene.get(), coordinates.data(), n, max_distance, nearest.data(), &args),
      SPHRAY_OK);
  ASSERT_EQ(sphray_inside_d(scene.get(), coordinates.data(), n, inside.data(), &args), SPHRAY_OK);
  std::size_t found = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Nearestd want = scalar::nearest(v, points[i], max_distance);
    found += want.found() ? 1 : 0;
    ASSERT_TRUE(nearest[i].id == want.id && same(nearest[i].distance, want.distance) &&
                same(nearest[i].px, want.point.x) && same(nearest[i].py, want.point.y) &&
                same(nearest[i].pz, want.point.z))
        << what << ", point " << i;
    ASSERT_EQ(inside[i] != 0, scalar::nearest(v, points[i]).distance < 0) << what << ", " << i;
    const double radius = 0.5 * static_cast<double>(i % 5);
    std::vector<std::uint32_t> ids(v.count + 1), want_ids(v.count + 1);
    std::size_t total = 0;
    ASSERT_EQ(sphray_overlapping_d(scene.get(), &coordinates[3 * i], radius, ids.size(), ids.data(),
                                   &total),
              SPHRAY_OK);
    const std::size_t want_total = scalar::overlapping(v, points[i], radius, want_ids);
    ASSERT_EQ(total, want_total) << what << ", point " << i;
    ASSERT_TRUE(std::equal(ids.begin(), ids.begin() + total, want_ids.begin())) << what;
  }
  EXPECT_GT(found, 0u) << what;
}

// A maximum distance that prunes in some scenes and not in others.
double max_distance_for(std::size_t count, double scale) {
  return count % 2 == 0 ? INFINITY : 3.0 * scale;
}

// Brute force and trees (built flat, walked, for a named instruction set), at the origin and
// 1e5 out, with and without masks: the answers of the C++ double scalar reference, bit for bit,
// for the rays' queries and the points'.
TEST(DoubleCApiAgreement, EveryQueryGivesTheScalarReferencesBits) {
  std::mt19937 rng(3720);
  const int isa = std::string(sphray_active_isa()) == "scalar"   ? SPHRAY_ISA_SCALAR
                  : std::string(sphray_active_isa()) == "sse4.2" ? SPHRAY_ISA_SSE4_2
                  : std::string(sphray_active_isa()) == "avx2"   ? SPHRAY_ISA_AVX2
                  : std::string(sphray_active_isa()) == "avx512" ? SPHRAY_ISA_AVX512
                                                                 : SPHRAY_ISA_NEON;
  for (const std::size_t count : {0u, 7u, 90u, 700u}) {
    for (const Vec3d at : {Vec3d{0, 0, 0}, Vec3d{1e5, -3e4, 2e5}}) {
      const double scale = 6.0 / std::cbrt(static_cast<double>(count) + 1.0);
      DoubleSpheres spheres = random_spheres(rng, count, at, scale);
      if (count > 0) spheres.storage[3][DoubleSpheres::kOffset + count / 2] = -1.0;  // never hit
      const SphereViewd v = spheres.view();
      std::vector<Rayd> rays(600);
      for (Rayd& r : rays)
        r = random_ray(rng, at, scale);
      std::vector<std::uint32_t> masks(rays.size());
      for (std::uint32_t& m : masks)
        m = static_cast<std::uint32_t>(rng());
      for (const int accel : {SPHRAY_ACCEL_BRUTE, SPHRAY_ACCEL_BVH, SPHRAY_ACCEL_AUTO}) {
        for (const bool named : {false, true}) {
          if (named && accel == SPHRAY_ACCEL_BRUTE) continue;
          const CScene scene(v, accel, named ? isa : SPHRAY_ISA_AUTO);
          ASSERT_EQ(scene.status(), SPHRAY_OK) << sphray_last_error();
          const std::string what = std::to_string(count) + " spheres, accel " +
                                   std::to_string(accel) + (named ? ", isa named" : "");
          if (count == 0) {
            std::vector<sphray_hit_d> hits(rays.size());
            std::vector<sphray_ray_d> c_rays(rays.size());
            for (std::size_t i = 0; i < rays.size(); ++i)
              c_rays[i] = to_c(rays[i]);
            ASSERT_EQ(
                sphray_intersect_d(scene.get(), c_rays.data(), rays.size(), hits.data(), nullptr),
                SPHRAY_OK);
            for (const sphray_hit_d& h : hits)
              ASSERT_EQ(h.id, SPHRAY_NO_HIT);
            continue;
          }
          expect_agreement(scene, v, rays, {}, what);
          std::vector<Vec3d> points(200);
          for (std::size_t i = 0; i < points.size(); ++i)
            points[i] = i % 4 == 0 ? Vec3d{v.cx[i % count], v.cy[i % count], v.cz[i % count]}
                                   : at + scale * in_box(rng, 12.0);
          expect_point_agreement(scene, v, points, max_distance_for(count, scale), what);
          DoubleSpheres masked = spheres;
          ASSERT_EQ(
              sphray_scene_set_masks(scene.get(), masked.masks.data() + DoubleSpheres::kOffset, 0),
              SPHRAY_OK);
          expect_agreement(scene, masked.view(true), rays, masks, what + ", masked");
        }
      }
    }
  }
}

// What the doors are for: a 1 mm sphere on a 10 km ground 100 km from the origin, a ray from
// 5 cm away towards the small sphere's centre. In double it is hit 4.9 cm out (to 1e-9 m); the
// float calls, given the same numbers rounded to float (whose spacing there is 7.8 mm), answer
// millimetres off.
TEST(DoubleCApiAgreement, AMillimetreSphereAHundredKilometresOut) {
  const Vec3d contact{1e5, 0.0, 0.0};
  const double cx[2] = {contact.x, contact.x}, cy[2] = {contact.y - 1e4, contact.y + 1e-3},
               cz[2] = {contact.z, contact.z}, r[2] = {1e4, 1e-3};
  sphray_scene* scene = nullptr;
  ASSERT_EQ(sphray_scene_create_d(cx, cy, cz, r, 2, 0, nullptr, &scene), SPHRAY_OK);
  const sphray_ray_d ray{contact.x - 0.05, contact.y + 1e-3, 0.0, 1.0, 0.0, 0.0, 0.0, INFINITY};
  sphray_hit_d hit;
  ASSERT_EQ(sphray_intersect_d(scene, &ray, 1, &hit, nullptr), SPHRAY_OK);
  EXPECT_EQ(hit.id, 1u);
  EXPECT_NEAR(hit.t, 0.05 - 1e-3, 1e-9);
  int precision = -1;
  ASSERT_EQ(sphray_scene_precision(scene, &precision), SPHRAY_OK);
  EXPECT_EQ(precision, SPHRAY_PRECISION_DOUBLE);
  sphray_scene_release(scene);

  float fx[2], fy[2], fz[2], fr[2];
  for (int i = 0; i < 2; ++i)
    fx[i] = static_cast<float>(cx[i]), fy[i] = static_cast<float>(cy[i]),
    fz[i] = static_cast<float>(cz[i]), fr[i] = static_cast<float>(r[i]);
  ASSERT_EQ(sphray_scene_create(fx, fy, fz, fr, 2, 0, nullptr, &scene), SPHRAY_OK);
  const sphray_ray fray{static_cast<float>(ray.ox),
                        static_cast<float>(ray.oy),
                        0.0f,
                        1.0f,
                        0.0f,
                        0.0f,
                        0.0f,
                        INFINITY};
  sphray_hit fhit;
  ASSERT_EQ(sphray_intersect(scene, &fray, 1, &fhit, nullptr), SPHRAY_OK);
  EXPECT_FALSE(fhit.id == 1u && std::fabs(fhit.t - (0.05 - 1e-3)) < 1e-3)
      << "float placed the sphere to a millimetre: the test no longer shows what double is for";
  sphray_scene_release(scene);
}

// refit_d: new doubles for the same spheres, brute force and tree answering for them.
TEST(DoubleCApiAgreement, RefitAnswersForTheNewSpheres) {
  std::mt19937 rng(3721);
  const Vec3d at{2e5, 0, 0};
  const DoubleSpheres before = random_spheres(rng, 300, at, 0.5);
  const DoubleSpheres after = random_spheres(rng, 300, at, 0.5);
  std::vector<Rayd> rays(400);
  for (Rayd& r : rays)
    r = random_ray(rng, at, 0.5);
  for (const int accel : {SPHRAY_ACCEL_BRUTE, SPHRAY_ACCEL_BVH}) {
    const CScene scene(before.view(), accel);
    ASSERT_EQ(scene.status(), SPHRAY_OK);
    const SphereViewd v = after.view();
    ASSERT_EQ(sphray_scene_refit_d(scene.get(), v.cx, v.cy, v.cz, v.radius, v.count, 0), SPHRAY_OK);
    expect_agreement(scene, v, rays, {}, "refitted, accel " + std::to_string(accel));
  }
}

// A scene keeps the precision it was created in: the other precision's calls are refused,
// with a message naming the right ones, even for empty work; the calls for either precision
// (size, isa, masks, release) take both.
TEST(CApiPrecision, ScenesRefuseTheOtherPrecisionsCalls) {
  const double dx[1] = {0}, dr[1] = {1};
  const float fx[1] = {0}, fr[1] = {1};
  sphray_scene *d = nullptr, *f = nullptr;
  ASSERT_EQ(sphray_scene_create_d(dx, dx, dx, dr, 1, 0, nullptr, &d), SPHRAY_OK);
  ASSERT_EQ(sphray_scene_create(fx, fx, fx, fr, 1, 0, nullptr, &f), SPHRAY_OK);
  const sphray_ray fray{0, 0, -5, 0, 0, 1, 0, INFINITY};
  const sphray_ray_d dray{0, 0, -5, 0, 0, 1, 0, INFINITY};
  sphray_hit fhit;
  sphray_hit_d dhit;
  sphray_hit_surface fs;
  sphray_hit_surface_d ds;
  unsigned char flag;
  std::size_t n;
  std::uint32_t id;
  float t;
  const float point[3] = {0, 0, 0};
  const sphray_ray_arrays arrays{point, point, point, point, point, point, nullptr, nullptr};
  const double dpoint3[3] = {0, 0, 0};
  const sphray_ray_arrays_d darrays{dpoint3, dpoint3, dpoint3, dpoint3,
                                    dpoint3, dpoint3, nullptr, nullptr};
  double dt;
  sphray_nearest_sphere nearest;
  const double dpoint[3] = {0, 0, 0};
  sphray_nearest_sphere_d dnearest;
  for (const std::size_t count : {1u, 0u}) {
    const auto refused = [&](int status, const char* call) {
      EXPECT_EQ(status, SPHRAY_ERROR_PRECISION) << call << ", count " << count;
      EXPECT_NE(std::string(sphray_last_error()).find(call), std::string::npos)
          << sphray_last_error();
    };
    refused(sphray_intersect(d, &fray, count, &fhit, nullptr), "sphray_intersect");
    refused(sphray_occluded(d, &fray, count, &flag, nullptr), "sphray_occluded");
    refused(sphray_intersect_arrays(d, &arrays, count, &t, &id, nullptr),
            "sphray_intersect_arrays");
    refused(sphray_intersect_arrays_d(f, &darrays, count, &dt, &id, nullptr),
            "sphray_intersect_arrays_d");
    refused(sphray_surface(d, &fray, &fhit, count, &fs), "sphray_surface");
    refused(sphray_intersect_all(d, &fray, count, 1, &fhit, nullptr, &n, nullptr),
            "sphray_intersect_all");
    refused(sphray_intersect_nearest(d, &fray, count, 1, &fhit, nullptr, &n, nullptr),
            "sphray_intersect_nearest");
    refused(sphray_count_hits(d, &fray, count, &n, nullptr), "sphray_count_hits");
    refused(sphray_nearest(d, point, count, INFINITY, &nearest, nullptr), "sphray_nearest");
    refused(sphray_inside(d, point, count, &flag, nullptr), "sphray_inside");
    refused(sphray_intersect_d(f, &dray, count, &dhit, nullptr), "sphray_intersect_d");
    refused(sphray_occluded_d(f, &dray, count, &flag, nullptr), "sphray_occluded_d");
    refused(sphray_surface_d(f, &dray, &dhit, count, &ds), "sphray_surface_d");
    refused(sphray_intersect_all_d(f, &dray, count, 1, &dhit, nullptr, &n, nullptr),
            "sphray_intersect_all_d");
    refused(sphray_intersect_nearest_d(f, &dray, count, 1, &dhit, nullptr, &n, nullptr),
            "sphray_intersect_nearest_d");
    refused(sphray_count_hits_d(f, &dray, count, &n, nullptr), "sphray_count_hits_d");
    refused(sphray_nearest_d(f, dpoint, count, INFINITY, &dnearest, nullptr), "sphray_nearest_d");
    refused(sphray_inside_d(f, dpoint, count, &flag, nullptr), "sphray_inside_d");
  }
  EXPECT_EQ(sphray_overlapping_d(f, dpoint, 1.0, 1, &id, &n), SPHRAY_ERROR_PRECISION);
  EXPECT_EQ(sphray_overlapping(d, point, 1.0f, 1, &id, &n), SPHRAY_ERROR_PRECISION);
  EXPECT_EQ(sphray_scene_refit(d, fx, fx, fx, fr, 1, 0), SPHRAY_ERROR_PRECISION);
  EXPECT_EQ(sphray_scene_refit_d(f, dx, dx, dx, dr, 1, 0), SPHRAY_ERROR_PRECISION);

  // The right precision's calls still answer, and the shared calls take both.
  ASSERT_EQ(sphray_intersect_d(d, &dray, 1, &dhit, nullptr), SPHRAY_OK);
  EXPECT_EQ(dhit.id, 0u);
  EXPECT_EQ(dhit.t, 4.0);
  for (sphray_scene* scene : {d, f}) {
    int precision = -1, isa = 0;
    ASSERT_EQ(sphray_scene_precision(scene, &precision), SPHRAY_OK);
    EXPECT_EQ(precision, scene == d ? SPHRAY_PRECISION_DOUBLE : SPHRAY_PRECISION_FLOAT);
    ASSERT_EQ(sphray_scene_size(scene, &n), SPHRAY_OK);
    EXPECT_EQ(n, 1u);
    EXPECT_EQ(sphray_scene_isa(scene, &isa), SPHRAY_OK);
    EXPECT_NE(isa, SPHRAY_ISA_AUTO);
    const std::uint32_t none = 0;
    EXPECT_EQ(sphray_scene_set_masks(scene, &none, 0), SPHRAY_OK);
  }
  // A ray with every bit no longer sees the sphere whose mask is 0.
  ASSERT_EQ(sphray_intersect_d(d, &dray, 1, &dhit, nullptr), SPHRAY_OK);
  EXPECT_EQ(dhit.id, SPHRAY_NO_HIT);
  EXPECT_EQ(sphray_scene_release(d), SPHRAY_OK);
  EXPECT_EQ(sphray_scene_release(f), SPHRAY_OK);
  EXPECT_EQ(sphray_intersect_d(d, &dray, 1, &dhit, nullptr), SPHRAY_ERROR_RELEASED_SCENE);
  int precision;
  EXPECT_EQ(sphray_scene_precision(d, &precision), SPHRAY_ERROR_RELEASED_SCENE);
}

// The double arrays' own checks: NULL, a stride not a multiple of 8, a pointer not aligned for
// double, a refit of another count; none leaves a scene behind or crashes.
TEST(CApiPrecision, DoubleArraysAreChecked) {
  alignas(16) double storage[9] = {0, 0, 0, 0, 0, 0, 0, 0, 1};
  const double* at = storage;
  sphray_scene* scene = nullptr;
  EXPECT_EQ(sphray_scene_create_d(nullptr, at, at, at, 1, 0, nullptr, &scene),
            SPHRAY_ERROR_NULL_POINTER);
  EXPECT_EQ(sphray_scene_create_d(at, at, at, at, 1, 0, nullptr, nullptr),
            SPHRAY_ERROR_NULL_POINTER);
  EXPECT_EQ(sphray_scene_create_d(at, at, at, at, 2, 4, nullptr, &scene),
            SPHRAY_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sphray_last_error()).find("sizeof(double)"), std::string::npos);
  const auto* misaligned =
      reinterpret_cast<const double*>(reinterpret_cast<const unsigned char*>(storage) + 4);
  EXPECT_EQ(sphray_scene_create_d(misaligned, at, at, at, 1, 0, nullptr, &scene),
            SPHRAY_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sphray_last_error()).find("aligned for double"), std::string::npos);
  EXPECT_EQ(scene, nullptr);
  // An array of structures: four doubles a sphere, 32 bytes apart.
  ASSERT_EQ(
      sphray_scene_create_d(storage, storage + 1, storage + 2, storage + 3, 2, 32, nullptr, &scene),
      SPHRAY_OK);
  EXPECT_EQ(sphray_scene_refit_d(scene, at, at, at, at, 3, 0), SPHRAY_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(sphray_scene_refit_d(scene, at, at, at, nullptr, 2, 0), SPHRAY_ERROR_NULL_POINTER);
  const double dirs[3] = {0, 0, 1};
  sphray_ray_d out;
  EXPECT_EQ(sphray_spawn_d(nullptr, dirs, 1, &out), SPHRAY_ERROR_NULL_POINTER);
  EXPECT_EQ(sphray_spawn_d(nullptr, nullptr, 0, nullptr), SPHRAY_OK);  // empty work
  EXPECT_EQ(sphray_scene_release(scene), SPHRAY_OK);
}

// Every _d call of a batch, hostile: a NULL scene, a NULL input or output, a count beyond the
// address space, a released scene; each refused with its status and its function's name in
// the message, none crashing; and each answering once the arguments are right.
TEST(CApiPrecision, DoubleCallsRefuseNullPointersBadCountsAndReleasedScenes) {
  const double c[2] = {0, 3}, r[2] = {1, 1};
  sphray_scene* scene = nullptr;
  ASSERT_EQ(sphray_scene_create_d(c, c, c, r, 2, 0, nullptr, &scene), SPHRAY_OK);
  const sphray_ray_d rays[2] = {{0, 0, -5, 0, 0, 1, 0, INFINITY}, {9, 9, 9, 1, 0, 0, 0, INFINITY}};
  const double points[6] = {0, 0, 0, 9, 9, 9};
  sphray_hit_d hits[2];
  sphray_hit_surface_d surfaces[2];
  sphray_nearest_sphere_d nearest[2];
  unsigned char flags[2];
  std::size_t counts[2];
  // call(scene, input or NULL, output or NULL, count): one entry per _d batch call.
  using Call = std::function<int(const sphray_scene*, bool, bool, std::size_t)>;
  const std::vector<std::pair<const char*, Call>> calls = {
      {"sphray_intersect_d",
       [&](const sphray_scene* s, bool in, bool out, std::size_t n) {
         return sphray_intersect_d(s, in ? rays : nullptr, n, out ? hits : nullptr, nullptr);
       }},
      {"sphray_occluded_d",
       [&](const sphray_scene* s, bool in, bool out, std::size_t n) {
         return sphray_occluded_d(s, in ? rays : nullptr, n, out ? flags : nullptr, nullptr);
       }},
      {"sphray_surface_d",
       [&](const sphray_scene* s, bool in, bool out, std::size_t n) {
         return sphray_surface_d(s, in ? rays : nullptr, hits, n, out ? surfaces : nullptr);
       }},
      {"sphray_intersect_all_d",
       [&](const sphray_scene* s, bool in, bool out, std::size_t n) {
         return sphray_intersect_all_d(s, in ? rays : nullptr, n, 0, nullptr, nullptr,
                                       out ? counts : nullptr, nullptr);
       }},
      {"sphray_intersect_nearest_d",
       [&](const sphray_scene* s, bool in, bool out, std::size_t n) {
         return sphray_intersect_nearest_d(s, in ? rays : nullptr, n, 1, hits, nullptr,
                                           out ? counts : nullptr, nullptr);
       }},
      {"sphray_count_hits_d",
       [&](const sphray_scene* s, bool in, bool out, std::size_t n) {
         return sphray_count_hits_d(s, in ? rays : nullptr, n, out ? counts : nullptr, nullptr);
       }},
      {"sphray_nearest_d",
       [&](const sphray_scene* s, bool in, bool out, std::size_t n) {
         return sphray_nearest_d(s, in ? points : nullptr, n, INFINITY, out ? nearest : nullptr,
                                 nullptr);
       }},
      {"sphray_inside_d",
       [&](const sphray_scene* s, bool in, bool out, std::size_t n) {
         return sphray_inside_d(s, in ? points : nullptr, n, out ? flags : nullptr, nullptr);
       }},
  };
  const auto expect = [](int status, int want, const char* f, const char* says) {
    EXPECT_EQ(status, want) << f;
    const std::string message = sphray_last_error();
    EXPECT_NE(message.find(f), std::string::npos) << message;
    EXPECT_NE(message.find(says), std::string::npos) << message;
  };
  const std::size_t huge = PTRDIFF_MAX;
  for (const auto& [f, call] : calls) {
    expect(call(nullptr, true, true, 2), SPHRAY_ERROR_NULL_POINTER, f, "scene is NULL");
    expect(call(scene, false, true, 2), SPHRAY_ERROR_NULL_POINTER, f, "is NULL");
    expect(call(scene, true, false, 2), SPHRAY_ERROR_NULL_POINTER, f, "is NULL");
    expect(call(scene, true, true, huge), SPHRAY_ERROR_TOO_LARGE, f, "count exceeds");
    EXPECT_EQ(call(scene, true, true, 2), SPHRAY_OK) << f << ": " << sphray_last_error();
  }
  std::size_t total = 0;
  expect(sphray_overlapping_d(scene, nullptr, 1.0, 0, nullptr, &total), SPHRAY_ERROR_NULL_POINTER,
         "sphray_overlapping_d", "centre is NULL");
  ASSERT_EQ(sphray_scene_release(scene), SPHRAY_OK);
  for (const auto& [f, call] : calls)
    expect(call(scene, true, true, 2), SPHRAY_ERROR_RELEASED_SCENE, f, "released");
  expect(sphray_overlapping_d(scene, points, 1.0, 0, nullptr, &total), SPHRAY_ERROR_RELEASED_SCENE,
         "sphray_overlapping_d", "released");
  expect(sphray_scene_refit_d(scene, c, c, c, r, 2, 0), SPHRAY_ERROR_RELEASED_SCENE,
         "sphray_scene_refit_d", "released");
}

}  // namespace
