// The point queries in double (nearest, inside, overlapping, point_queries.hpp): every
// instruction set's brute force and tree against the double scalar reference, bit for bit, and
// the reference against a long-double one; millimetre spheres 100 km out, where float's
// distances are off by millimetres and double's by far less than a micrometre; the contract's
// invalid input.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "double_support.hpp"
#include "test_support.hpp"

namespace sphray {
namespace {

using namespace test::doubles;

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}
bool same_bits(const Nearestd& a, const Nearestd& b) {
  return a.id == b.id && same_bits(a.distance, b.distance) && same_bits(a.point.x, b.point.x) &&
         same_bits(a.point.y, b.point.y) && same_bits(a.point.z, b.point.z);
}

// |p - c| - r in long double.
Real exact_distance(const SphereViewd& v, std::size_t i, Vec3d p) {
  const Real gx = Real{v.cx[i]} - p.x, gy = Real{v.cy[i]} - p.y, gz = Real{v.cz[i]} - p.z;
  return std::sqrt(gx * gx + gy * gy + gz * gz) - v.radius[i];
}

bool valid(const SphereViewd& v, std::size_t i) {
  return std::isfinite(v.cx[i]) && std::isfinite(v.cy[i]) && std::isfinite(v.cz[i]) &&
         v.radius[i] >= 0x1p-511 && v.radius[i] < 0x1p512;
}

// Points in and around the scene, and sphere centres.
std::vector<Vec3d> points_for(const SphereViewd& v, Vec3d at, double scale, std::size_t n,
                              std::mt19937& rng) {
  std::vector<Vec3d> points;
  for (std::size_t i = 0; i < n; ++i) {
    if (v.count > 0 && i % 8 == 0) {
      const std::size_t s = rng() % v.count;
      points.push_back({v.cx[s], v.cy[s], v.cz[s]});
    } else {
      points.push_back(at + scale * in_box(rng, 12.0));
    }
  }
  return points;
}

// Each kernel's brute force and a tree for its instruction set against the scalar reference,
// on scenes of 0 to 2000 spheres at the origin and 1e5 out, with some invalid spheres; the
// reference against long double (the nearest distance, and overlapping's ids where no sphere
// lies within rounding of the ball).
TEST(DoublePoints, EveryKernelAndTreeMatchTheReferences) {
  std::mt19937 rng(3730);
  const std::size_t counts[] = {0, 1, 3, 17, 100, 2000};
  const Vec3d places[] = {{0, 0, 0}, {1e5, -2e5, 3e4}};
  std::size_t found = 0, asked = 0;
  for (const std::size_t n : counts) {
    for (const Vec3d at : places) {
      const double scale = 6.0 / std::cbrt(static_cast<double>(n) + 1.0);
      DoubleSpheres scene = random_spheres(rng, n, at, scale);
      for (std::size_t i = 5; i < n; i += 11)
        scene.storage[3][DoubleSpheres::kOffset + i] = i % 2 ? -1.0 : kNaN;  // never found
      const SphereViewd v = scene.view();
      const std::vector<Vec3d> points = points_for(v, at, scale, test::scaled(300), rng);
      for (const EntryTable* k : test::runnable_kernels()) {
        const SphereBVHd tree(v, k->isa);
        for (const Vec3d p : points) {
          const Nearestd want = scalar::nearest(v, p);
          const Hitd brute = k->nearest_d(v, p, kInf);
          ASSERT_EQ(brute.id, want.id) << test::name_of(k) << ", " << n << " spheres";
          if (want.found()) {
            ASSERT_TRUE(same_bits(brute.t, want.distance)) << test::name_of(k);
          }
          ASSERT_TRUE(same_bits(nearest(tree, p), want)) << test::name_of(k) << ", " << n;
          ASSERT_EQ(inside(tree, p), want.found() && want.distance < 0) << test::name_of(k);
          const double radius = scale * uniform(rng, 0.0, 3.0);
          std::vector<std::uint32_t> from_tree(n + 1), from_reference(n + 1);
          const std::size_t total = scalar::overlapping(v, p, radius, from_reference);
          ASSERT_EQ(overlapping(tree, p, radius, from_tree), total) << test::name_of(k);
          ASSERT_TRUE(
              std::equal(from_tree.begin(), from_tree.begin() + total, from_reference.begin()))
              << test::name_of(k);
          ++asked;
          found += want.found() ? 1 : 0;
        }
      }
      // The reference against long double: the nearest distance to a relative 2^-50 of the
      // scale of the numbers, and the overlap decided wherever rounding cannot decide it.
      for (const Vec3d p : points) {
        const Nearestd got = scalar::nearest(v, p);
        Real best = std::numeric_limits<Real>::infinity();
        for (std::size_t i = 0; i < n; ++i)
          if (valid(v, i)) best = std::min(best, exact_distance(v, i, p));
        if (!got.found()) {
          ASSERT_TRUE(std::isinf(best));  // no valid sphere at all
          continue;
        }
        const Real tolerance = 0x1p-48L * (std::fabs(Real{p.x}) + std::fabs(Real{p.y}) +
                                           std::fabs(Real{p.z}) + 30 * scale);
        ASSERT_NEAR(static_cast<double>(got.distance), static_cast<double>(best),
                    static_cast<double>(tolerance));
        ASSERT_NEAR(static_cast<double>(exact_distance(v, got.id, p)), static_cast<double>(best),
                    static_cast<double>(2 * tolerance));
      }
    }
  }
  EXPECT_GT(found, asked / 2);
}

// What double is for: 2000 spheres of 1 mm radius, 2.5 mm apart on average, 100 km out. Double
// finds the nearest sphere and its distance to within a nanometre, through brute force and a
// tree; float, asked the same (rounded), is off by millimetres.
TEST(DoublePoints, MillimetreSpheresAHundredKilometresOut) {
  std::mt19937 rng(3731);
  const Vec3d at{1e5, -1e5, 5e4};
  DoubleSpheres scene;
  for (std::size_t i = 0; i < 2000; ++i)
    scene.add(at + 0.015 * in_box(rng, 1.0), 1e-3 * uniform(rng, 0.5, 1.0));
  const SphereViewd v = scene.view();
  const SphereBVHd tree(v);
  std::vector<float> fx, fy, fz, fr;
  for (std::size_t i = 0; i < v.count; ++i) {
    fx.push_back(static_cast<float>(v.cx[i])), fy.push_back(static_cast<float>(v.cy[i]));
    fz.push_back(static_cast<float>(v.cz[i])), fr.push_back(static_cast<float>(v.radius[i]));
  }
  const SphereView float_view{fx.data(), fy.data(), fz.data(), fr.data(), v.count};
  double worst_double = 0, worst_float = 0;
  for (std::size_t i = 0; i < test::scaled(500); ++i) {
    const Vec3d p = at + 0.02 * in_box(rng, 1.0);
    Real best = std::numeric_limits<Real>::infinity();
    for (std::size_t s = 0; s < v.count; ++s)
      best = std::min(best, exact_distance(v, s, p));
    const Nearestd brute = nearest(v, p), walked = nearest(tree, p);
    ASSERT_TRUE(same_bits(brute, walked));
    worst_double = std::max(worst_double, static_cast<double>(std::fabs(brute.distance - best)));
    const Nearest f = nearest(float_view, Vec3{static_cast<float>(p.x), static_cast<float>(p.y),
                                               static_cast<float>(p.z)});
    worst_float = std::max(worst_float, static_cast<double>(std::fabs(f.distance - best)));
  }
  EXPECT_LT(worst_double, 1e-9);
  EXPECT_GT(worst_float, 1e-3);
}

// The pairs of reference: for each valid sphere i, the spheres j > i that scalar::overlapping
// lists for the ball of sphere i (the contract's definition, in double).
std::vector<IdPair> reference_pairs(const SphereViewd& v) {
  std::vector<IdPair> pairs;
  std::vector<std::uint32_t> ids(v.count);
  for (std::uint32_t i = 0; i < v.count; ++i) {
    if (!valid(v, i)) continue;
    const std::size_t n = scalar::overlapping(v, {v.cx[i], v.cy[i], v.cz[i]}, v.radius[i], ids);
    for (std::size_t k = 0; k < n; ++k)
      if (ids[k] > i) pairs.push_back({i, ids[k]});
  }
  return pairs;
}

std::vector<IdPair> sorted(std::vector<IdPair> pairs) {
  std::sort(pairs.begin(), pairs.end(), [](IdPair a, IdPair b) {
    return a.first != b.first ? a.first < b.first : a.second < b.second;
  });
  return pairs;
}

// overlapping_pairs on double trees of every instruction set, whole and in three parts, against
// the reference; and millimetre spheres 100 km out, 2 mm apart plus or minus a micrometre,
// which double pairs exactly as they overlap or not (float would round their centres to its
// 7.8 mm spacing there).
TEST(DoublePoints, OverlappingPairsAreTheReferencesPairsEachOnce) {
  std::mt19937 rng(3732);
  std::size_t total = 0;
  for (const std::size_t n : {0u, 5u, 17u, 300u, 2000u}) {
    for (const Vec3d at : {Vec3d{0, 0, 0}, Vec3d{1e5, -2e5, 3e4}}) {
      const double scale = 6.0 / std::cbrt(static_cast<double>(n) + 1.0);
      DoubleSpheres scene = random_spheres(rng, n, at, 0.5 * scale);
      for (std::size_t i = 3; i < n; i += 13)
        scene.storage[3][DoubleSpheres::kOffset + i] = -1.0;  // never paired
      const SphereViewd v = scene.view();
      const std::vector<IdPair> want = sorted(reference_pairs(v));
      total += want.size();
      for (const EntryTable* k : test::runnable_kernels()) {
        const SphereBVHd tree(v, k->isa);
        std::vector<IdPair> whole, parts;
        overlapping_pairs(tree, whole);
        for (std::size_t part = 0; part < 3; ++part)
          overlapping_pairs(tree, parts, part, 3);
        ASSERT_EQ(whole.size(), want.size()) << test::name_of(k) << ", " << n << " spheres";
        EXPECT_EQ(sorted(whole), want) << test::name_of(k) << ", " << n << " spheres";
        EXPECT_EQ(sorted(parts), want) << test::name_of(k) << ", " << n << " spheres";
      }
    }
  }
  EXPECT_GT(total, 1000u);

  // A row of 1 mm spheres along x, 100 km out: neighbours 2 mm - 1 um apart overlap, 2 mm + 1 um
  // apart do not.
  DoubleSpheres row;
  std::vector<IdPair> touching;
  double x = 1e5;
  for (std::uint32_t i = 0; i < 400; ++i) {
    row.add({x, -3e4, 7e4}, 1e-3);
    const bool overlap = rng() % 2 == 0;
    if (overlap && i + 1 < 400) touching.push_back({i, i + 1});
    x += overlap ? 2e-3 - 1e-6 : 2e-3 + 1e-6;
  }
  for (const EntryTable* k : test::runnable_kernels()) {
    const SphereBVHd tree(row.view(), k->isa);
    std::vector<IdPair> pairs;
    overlapping_pairs(tree, pairs);
    EXPECT_EQ(sorted(pairs), touching) << test::name_of(k);
  }
}

// The contract's invalid input: non-finite points, a NaN maximum, a negative or NaN radius
// give the empty answer; invalid spheres (NaN or infinite centre, radius outside
// [2^-511, 2^512)) are never found; a maximum distance prunes; the batch forms check sizes.
TEST(DoublePoints, InvalidInputGivesTheEmptyAnswer) {
  DoubleSpheres scene;
  scene.add({0, 0, 0}, 1.0);
  scene.add({0.5, 0, 0}, 0x1p-512);  // below the smallest valid radius
  scene.add({kNaN, 0, 0}, 5.0);
  scene.add({0, kInf, 0}, 5.0);
  scene.add({0.2, 0, 0}, 0x1p512);  // the first invalid radius
  scene.add({3, 0, 0}, 0.5);
  const SphereViewd v = scene.view();
  for (const EntryTable* k : test::runnable_kernels()) {
    const SphereBVHd tree(v, k->isa);
    for (const Vec3d bad : {Vec3d{kNaN, 0, 0}, Vec3d{0, kInf, 0}, Vec3d{0, 0, -kInf}}) {
      EXPECT_FALSE(nearest(tree, bad).found()) << test::name_of(k);
      EXPECT_EQ(k->nearest_d(v, bad, kInf).id, kNoHit) << test::name_of(k);
      EXPECT_FALSE(inside(tree, bad)) << test::name_of(k);
      EXPECT_EQ(overlapping(tree, bad, 10.0, {}), 0u) << test::name_of(k);
    }
    const Vec3d p{0.5, 0, 0};
    const Nearestd n = nearest(tree, p);
    EXPECT_EQ(n.id, 0u) << test::name_of(k);
    EXPECT_EQ(n.distance, -0.5) << test::name_of(k);
    EXPECT_FALSE(nearest(tree, Vec3d{3, 4, 0}, 3.0).found()) << test::name_of(k);  // 3.5 away
    EXPECT_EQ(nearest(tree, Vec3d{3, 4, 0}, 3.5).id, 5u) << test::name_of(k);
    EXPECT_FALSE(nearest(tree, p, kNaN).found()) << test::name_of(k);
    EXPECT_EQ(overlapping(tree, p, -1.0, {}), 0u) << test::name_of(k);
    EXPECT_EQ(overlapping(tree, p, kNaN, {}), 0u) << test::name_of(k);
    std::vector<std::uint32_t> ids(6);
    ASSERT_EQ(overlapping(tree, p, 100.0, ids), 2u) << test::name_of(k);
    EXPECT_EQ(ids[0], 0u);
    EXPECT_EQ(ids[1], 5u);
  }
  const std::vector<Vec3d> points{{0, 0, 0}, {3, 0, 0}, {9, 9, 9}};
  std::vector<Nearestd> out(3);
  bool flags[3];
  nearest(v, points, out);
  inside(v, points, std::span<bool>(flags, 3));
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_TRUE(same_bits(out[i], nearest(v, points[i])));
    EXPECT_EQ(flags[i], inside(v, points[i]));
  }
  EXPECT_TRUE(flags[0] && flags[1] && !flags[2]);
  std::vector<Nearestd> short_out(2);
  EXPECT_THROW(nearest(v, points, short_out), std::length_error);
}

}  // namespace
}  // namespace sphray
