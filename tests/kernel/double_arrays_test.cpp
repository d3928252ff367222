// Rays, hits and surfaces as one array per quantity in double (RayArraysd, HitArraysd,
// SurfaceArraysd): every stream call gives each ray the bits its single call gives, through a
// view and a tree, with and without bounds and masks, over more rays than one chunk; and the
// calls refuse arrays of other counts and null arrays as float's do.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "double_support.hpp"

namespace sphray {
namespace {

using namespace test::doubles;
using test::doubles::same_bits;

bool same_bits(Vec3d a, Vec3d b) {
  return std::bit_cast<std::uint64_t>(a.x) == std::bit_cast<std::uint64_t>(b.x) &&
         std::bit_cast<std::uint64_t>(a.y) == std::bit_cast<std::uint64_t>(b.y) &&
         std::bit_cast<std::uint64_t>(a.z) == std::bit_cast<std::uint64_t>(b.z);
}

// Rays as columns, each array starting one double into its storage (no alignment assumed).
struct RayColumnsd {
  std::vector<double> column[8];  // ox, oy, oz, dx, dy, dz, tmin, tmax
  std::vector<std::uint32_t> masks;

  explicit RayColumnsd(const std::vector<Rayd>& rays) {
    for (std::vector<double>& c : column)
      c.assign(1, 0.0);
    masks.assign(1, 0u);
    for (const Rayd& r : rays) {
      const double values[8] = {r.origin.x, r.origin.y, r.origin.z, r.dir.x,
                                r.dir.y,    r.dir.z,    r.tmin,     r.tmax};
      for (std::size_t k = 0; k < 8; ++k)
        column[k].push_back(values[k]);
      masks.push_back(r.mask);
    }
  }
  // bounds: tmin and tmax given (else null: 0 and infinity); with_masks: the masks given.
  RayArraysd arrays(bool bounds, bool with_masks) const {
    const auto at = [](const std::vector<double>& c) { return c.data() + 1; };
    return {at(column[0]),
            at(column[1]),
            at(column[2]),
            at(column[3]),
            at(column[4]),
            at(column[5]),
            bounds ? at(column[6]) : nullptr,
            bounds ? at(column[7]) : nullptr,
            with_masks ? masks.data() + 1 : nullptr,
            column[0].size() - 1};
  }
};

// 700 rays (two full chunks of 256 and a part), some bounded, some masked, around `at`.
std::vector<Rayd> bounded_rays(std::mt19937& rng, Vec3d at, double scale) {
  std::vector<Rayd> rays(700);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    rays[i] = random_ray(rng, at, scale);
    rays[i].tmin = i % 5 == 0 ? uniform(rng, 0.0, scale) : 0.0;
    rays[i].tmax = i % 7 == 0 ? uniform(rng, scale, 20 * scale) : kInf;
    rays[i].mask = i % 3 == 0 ? 0u : static_cast<std::uint32_t>(rng());
  }
  return rays;
}

TEST(DoubleArrays, IntersectGivesEachRayItsSingleCallsBits) {
  std::mt19937 rng(3730);
  for (const Vec3d at : {Vec3d{0, 0, 0}, Vec3d{1e5, -3e4, 2e5}}) {
    DoubleSpheres spheres = random_spheres(rng, 600, at, 0.6);
    for (std::size_t i = 0; i < spheres.size(); ++i)
      spheres.masks[DoubleSpheres::kOffset + i] = static_cast<std::uint32_t>(rng());
    const std::vector<Rayd> rays = bounded_rays(rng, at, 0.6);
    const RayColumnsd columns(rays);
    for (const bool with_masks : {false, true}) {
      const SphereViewd view = spheres.view(with_masks);
      const SphereBVHd tree(view);
      for (const bool bounds : {false, true}) {
        const RayArraysd arrays = columns.arrays(bounds, with_masks);
        std::vector<double> t(rays.size(), -1.0), tree_t(rays.size(), -1.0);
        std::vector<std::uint32_t> id(rays.size()), tree_id(rays.size());
        intersect(view, arrays, HitArraysd{t.data(), id.data(), t.size()});
        intersect(tree, arrays, HitArraysd{tree_t.data(), tree_id.data(), t.size()});
        std::size_t found = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
          const Rayd ray = arrays.at(i);
          const Hitd want = scalar::intersect(view, ray);
          found += want.found();
          const std::string what = std::string(bounds ? "bounds" : "no bounds") +
                                   (with_masks ? ", masks" : "") + ", ray " + std::to_string(i);
          ASSERT_TRUE(same_bits(Hitd{t[i], id[i]}, want)) << "view, " << what;
          ASSERT_TRUE(same_bits(Hitd{tree_t[i], tree_id[i]}, want)) << "tree, " << what;
        }
        EXPECT_GT(found, rays.size() / 10);
        EXPECT_LT(found, rays.size());
      }
    }
  }
}

TEST(DoubleArrays, SurfacesAndOffsetOriginsAnswerAsTheSingleCalls) {
  std::mt19937 rng(3731);
  const Vec3d at{-2e5, 1e4, 3e5};
  const DoubleSpheres spheres = random_spheres(rng, 300, at, 0.5);
  const SphereViewd view = spheres.view();
  const std::vector<Rayd> rays = bounded_rays(rng, at, 0.5);
  const RayColumnsd columns(rays);
  const RayArraysd arrays = columns.arrays(true, false);
  const std::size_t n = rays.size();
  std::vector<double> t(n);
  std::vector<std::uint32_t> id(n);
  const HitArraysd hits{t.data(), id.data(), n};
  intersect(view, arrays, hits);

  std::vector<double> s[9];
  for (std::vector<double>& c : s)
    c.resize(n);
  std::unique_ptr<bool[]> front(new bool[n]);
  const SurfaceArraysd out{s[0].data(),
                           s[1].data(),
                           s[2].data(),
                           s[3].data(),
                           s[4].data(),
                           s[5].data(),
                           front.get(),
                           s[6].data(),
                           s[7].data(),
                           s[8].data(),
                           n};
  surfaces(view, arrays, hits, out);
  // Leave each surface along its normal, the reverse for every other one.
  std::vector<double> d[3], o[3];
  for (std::size_t k = 0; k < 3; ++k)
    d[k].resize(n), o[k].resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double sign = i % 2 == 0 ? 1.0 : -1.0;
    d[0][i] = sign * s[3][i], d[1][i] = sign * s[4][i], d[2][i] = sign * s[5][i];
  }
  offset_origins(out, VectorArraysd{d[0].data(), d[1].data(), d[2].data(), n},
                 VectorOutArraysd{o[0].data(), o[1].data(), o[2].data(), n});
  std::size_t hit = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Surfaced want = surface(view, arrays.at(i), hits.at(i));
    const Surfaced got = out.at(i);
    hit += hits.at(i).found();
    ASSERT_TRUE(same_bits(got.point, want.point) && same_bits(got.normal, want.normal) &&
                same_bits(got.error, want.error) && got.front_face == want.front_face)
        << "ray " << i;
    const Vec3d origin = offset_origin(want, {d[0][i], d[1][i], d[2][i]});
    ASSERT_TRUE(same_bits(Vec3d{o[0][i], o[1][i], o[2][i]}, origin)) << "ray " << i;
  }
  EXPECT_GT(hit, n / 10);
}

TEST(DoubleArrays, RefuseOtherCountsAndNullArrays) {
  std::mt19937 rng(3732);
  const DoubleSpheres spheres = random_spheres(rng, 20, {0, 0, 0}, 1.0);
  const SphereViewd view = spheres.view();
  const SphereBVHd tree(view);
  const RayColumnsd columns(bounded_rays(rng, {0, 0, 0}, 1.0));
  const RayArraysd rays = columns.arrays(false, false);
  std::vector<double> t(rays.count);
  std::vector<std::uint32_t> id(rays.count);
  const HitArraysd hits{t.data(), id.data(), rays.count};
  EXPECT_THROW(intersect(view, rays, HitArraysd{t.data(), id.data(), 3}), std::length_error);
  EXPECT_THROW(intersect(tree, rays, HitArraysd{t.data(), id.data(), 3}), std::length_error);
  RayArraysd no_origin = rays;
  no_origin.oy = nullptr;
  EXPECT_THROW(intersect(view, no_origin, hits), std::invalid_argument);
  EXPECT_THROW(intersect(tree, no_origin, hits), std::invalid_argument);
  EXPECT_THROW(intersect(view, rays, HitArraysd{nullptr, id.data(), rays.count}),
               std::invalid_argument);
  // Empty work needs no arrays.
  EXPECT_NO_THROW(intersect(view, RayArraysd{}, HitArraysd{}));
  EXPECT_NO_THROW(intersect(tree, RayArraysd{}, HitArraysd{}));

  std::vector<double> s[9];
  for (std::vector<double>& c : s)
    c.resize(rays.count);
  std::unique_ptr<bool[]> front(new bool[rays.count]);
  SurfaceArraysd out{s[0].data(), s[1].data(), s[2].data(), s[3].data(), s[4].data(), s[5].data(),
                     front.get(), s[6].data(), s[7].data(), s[8].data(), rays.count};
  SurfaceArraysd short_out = out;
  short_out.count = 2;
  EXPECT_THROW(surfaces(view, rays, hits, short_out), std::length_error);
  SurfaceArraysd no_normal = out;
  no_normal.ny = nullptr;
  EXPECT_THROW(surfaces(view, rays, hits, no_normal), std::invalid_argument);
  const VectorArraysd dirs{s[0].data(), s[1].data(), nullptr, rays.count};
  const VectorOutArraysd origins{s[3].data(), s[4].data(), s[5].data(), rays.count};
  EXPECT_THROW(offset_origins(out, dirs, origins), std::invalid_argument);
  EXPECT_THROW(
      offset_origins(out, VectorArraysd{s[0].data(), s[1].data(), s[2].data(), 1}, origins),
      std::length_error);
}

}  // namespace
}  // namespace sphray
