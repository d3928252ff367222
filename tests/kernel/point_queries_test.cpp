// nearest, inside and overlapping (point_queries.hpp) against a long-double reference written
// here, on scenes of many shapes; every kernel, the dispatched queries, the trees and the scalar
// reference bit for bit alike; capacities smaller than the answer; the contract's invalid input.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "test_support.hpp"

namespace sphray {
namespace {

using L = long double;

bool valid(SphereView v, std::size_t i) {
  return std::isfinite(v.cx[i]) && std::isfinite(v.cy[i]) && std::isfinite(v.cz[i]) &&
         std::isfinite(v.radius[i]) && v.radius[i] > 0.0f;
}

// |p - c| - r in long double, and how far float's value of it may be off: a few units in the
// last place of |p - c| + r, widened a thousandfold.
L distance(SphereView v, std::size_t i, Vec3 p) {
  const L gx = L{v.cx[i]} - p.x, gy = L{v.cy[i]} - p.y, gz = L{v.cz[i]} - p.z;
  return std::sqrt(gx * gx + gy * gy + gz * gz) - v.radius[i];
}
L slack(SphereView v, std::size_t i, Vec3 p) {
  return 1e-4L * (std::fabs(distance(v, i, p)) + 2 * L{v.radius[i]} + 1e-3L);
}

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof(float)) == 0;
}
bool same_bits(const Nearest& a, const Nearest& b) {
  return a.id == b.id && same_bits(a.distance, b.distance) && same_bits(a.point.x, b.point.x) &&
         same_bits(a.point.y, b.point.y) && same_bits(a.point.z, b.point.z);
}

// Query points: random ones in and around the scene, sphere centres, and points on surfaces.
std::vector<Vec3> points_for(SphereView v, std::size_t n, std::mt19937& rng) {
  std::vector<Vec3> points;
  for (std::size_t i = 0; i < n; ++i) {
    if (v.count == 0) {
      points.push_back(test::random_in_box(rng, 14.0f));
      continue;
    }
    const std::size_t j = rng() % v.count;
    const Vec3 c{v.cx[j], v.cy[j], v.cz[j]};
    switch (i % 4) {
      case 0:
        points.push_back(c);
        break;
      case 1:
        points.push_back(c + v.radius[j] * test::unit_vector(rng));
        break;
      default:
        points.push_back(test::random_in_box(rng, 14.0f));
    }
  }
  return points;
}

TEST(PointQueries, WorkedCases) {
  SphereSoA s;
  s.add({0, 0, 0}, 1.0f);  // id 0
  s.add({5, 0, 0}, 2.0f);  // id 1
  s.add({5, 0, 0}, 1.0f);  // id 2, inside id 1
  const SphereView v = s.view();
  Nearest n = nearest(v, {2.5f, 0, 0});  // 1.5 from id 0, 0.5 from id 1
  EXPECT_EQ(n.id, 1u);
  EXPECT_EQ(n.distance, 0.5f);
  EXPECT_EQ(n.point, (Vec3{3, 0, 0}));
  n = nearest(v, {0, 0, 0});  // the centre of id 0: every surface point as near; +x
  EXPECT_EQ(n.id, 0u);
  EXPECT_EQ(n.distance, -1.0f);
  EXPECT_EQ(n.point, (Vec3{1, 0, 0}));
  n = nearest(v, {5, 0, 0.5f});  // deeper in id 1 (-1.5) than in id 2 (-0.5)
  EXPECT_EQ(n.id, 1u);
  EXPECT_EQ(n.distance, -1.5f);
  n = nearest(v, {2.5f, 0, 0}, 0.25f);  // nothing within 0.25
  EXPECT_FALSE(n.found());
  EXPECT_EQ(n.distance, 0.25f);
  EXPECT_EQ(n.point, (Vec3{2.5f, 0, 0}));
  EXPECT_TRUE(inside(v, {0.5f, 0, 0}));
  EXPECT_FALSE(inside(v, {1, 0, 0}));  // on the surface: the balls are open
  EXPECT_FALSE(inside(v, {2, 0, 0}));
  std::uint32_t ids[3];
  // 1.5 from id 0, 0.5 from id 1, 1.5 from id 2
  EXPECT_EQ(overlapping(v, {2.5f, 0, 0}, 1.6f, ids), 3u);
  EXPECT_EQ(ids[0], 0u);
  EXPECT_EQ(ids[1], 1u);
  EXPECT_EQ(ids[2], 2u);
  EXPECT_EQ(overlapping(v, {2.5f, 0, 0}, 1.5f, ids), 1u);  // touching is not overlapping
  EXPECT_EQ(ids[0], 1u);
}

TEST(PointQueries, InvalidInputGivesTheEmptyAnswer) {
  SphereSoA s;
  s.add({0, 0, 0}, 1.0f);
  s.add({0, 0, 0}, NAN);
  s.add({0, INFINITY, 0}, 1.0f);
  s.add({0, 0, 0}, -2.0f);
  const SphereBVH tree(s.view());
  const Vec3 bad_points[] = {{NAN, 0, 0}, {0, INFINITY, 0}, {0, 0, -INFINITY}};
  std::uint32_t ids[4] = {7, 7, 7, 7};
  for (const Vec3 p : bad_points) {
    EXPECT_FALSE(nearest(s.view(), p).found());
    EXPECT_FALSE(nearest(tree, p).found());
    EXPECT_FALSE(inside(s.view(), p));
    EXPECT_FALSE(inside(tree, p));
    EXPECT_EQ(overlapping(s.view(), p, 5.0f, ids), 0u);
    EXPECT_EQ(overlapping(tree, p, 5.0f, ids), 0u);
  }
  for (const float radius : {-1.0f, NAN, -INFINITY}) {
    EXPECT_EQ(overlapping(s.view(), {0, 0, 0}, radius, ids), 0u);
    EXPECT_EQ(overlapping(tree, {0, 0, 0}, radius, ids), 0u);
  }
  EXPECT_EQ(ids[0], 7u);  // nothing written
  EXPECT_FALSE(nearest(s.view(), {3, 0, 0}, NAN).found());
  EXPECT_FALSE(nearest(tree, {3, 0, 0}, NAN).found());
  // Only the valid sphere is ever found.
  EXPECT_EQ(nearest(s.view(), {3, 0, 0}).id, 0u);
  EXPECT_EQ(nearest(tree, {3, 0, 0}).id, 0u);
  EXPECT_EQ(overlapping(s.view(), {0, 0, 0}, INFINITY, ids), 1u);
  EXPECT_EQ(overlapping(tree, {0, 0, 0}, INFINITY, ids), 1u);
}

TEST(PointQueries, EveryKernelAndTreeMatchTheReferences) {
  std::mt19937 rng(16);
  const auto kernels = test::runnable_kernels();
  std::size_t queries = 0, decided_nearest = 0, decided_overlap = 0, found = 0, listed = 0;
  test::for_each_query_scene(
      rng, kernels, [&](SphereView v, const std::vector<SphereBVH>& trees, std::size_t n) {
        for (const Vec3 p : points_for(v, test::scaled(n >= 3000 ? 60 : 150), rng)) {
          ++queries;
          const float max_distance =
              (queries % 5 == 0) ? test::uniform(rng, -1.0f, 3.0f) : INFINITY;
          const float radius = test::uniform(rng, 0.0f, 3.0f);
          // The scalar reference is the answer every other form must give, bit for bit.
          const Nearest want = scalar::nearest(v, p, max_distance);
          std::vector<std::uint32_t> want_ids(n + 1);
          const std::size_t want_total = scalar::overlapping(v, p, radius, want_ids);
          want_ids.resize(want_total);
          found += want.found();
          listed += want_total;

          // Against long double, where float can decide.
          std::size_t best = v.count;
          bool nearest_decidable = true, overlap_decidable = true, inside_decidable = true;
          bool ref_inside = false;
          std::vector<std::uint32_t> ref_ids;
          // A point at a poisoned sphere's centre may be NaN or infinite: no answer at all.
          const bool point_ok = isfinite(p);
          for (std::size_t i = 0; i < v.count; ++i) {
            if (!valid(v, i) || !point_ok) continue;
            const L d = distance(v, i, p), e = slack(v, i, p);
            if (std::fabs(d - radius) <= e) overlap_decidable = false;
            if (std::fabs(d) <= e) inside_decidable = false;
            if (std::fabs(d - max_distance) <= e) nearest_decidable = false;
            if (d < radius) ref_ids.push_back(static_cast<std::uint32_t>(i));
            ref_inside |= d < 0;
            if (best == v.count || d < distance(v, best, p)) best = i;
          }
          if (best != v.count) {
            const L bd = distance(v, best, p);
            for (std::size_t i = 0; i < v.count; ++i) {
              if (i == best || !valid(v, i)) continue;
              const L d = distance(v, i, p);
              // Another sphere as near within rounding, but not the same sphere again.
              const bool twin = v.cx[i] == v.cx[best] && v.cy[i] == v.cy[best] &&
                                v.cz[i] == v.cz[best] && v.radius[i] == v.radius[best];
              if (!twin && std::fabs(d - bd) <= slack(v, i, p) + slack(v, best, p))
                nearest_decidable = false;
            }
          }
          if (nearest_decidable) {
            ++decided_nearest;
            const bool ref_found = best != v.count && distance(v, best, p) <= max_distance;
            ASSERT_EQ(want.found(), ref_found)
                << n << " spheres, point " << p.x << " " << p.y << " " << p.z << ", max "
                << max_distance << ", reference id " << best << " at "
                << static_cast<double>(best != v.count ? distance(v, best, p) : 0) << ", got id "
                << want.id << " at " << want.distance;
            if (ref_found) {
              EXPECT_EQ(want.id, best);
              EXPECT_NEAR(want.distance, static_cast<double>(distance(v, best, p)),
                          static_cast<double>(slack(v, best, p)));
              // The point lies on that sphere, on the side of p.
              const Vec3 c{v.cx[best], v.cy[best], v.cz[best]};
              const float r = v.radius[best];
              EXPECT_NEAR(length(want.point - c), r, 1e-5 * (r + length(c)));
            }
          }
          if (overlap_decidable) {
            ++decided_overlap;
            EXPECT_EQ(want_ids, ref_ids) << n << " spheres, radius " << radius;
          }
          if (inside_decidable) {
            EXPECT_EQ(inside(v, p), ref_inside);
          }

          // Every kernel, the dispatched queries and every tree, with short outputs too.
          auto check_overlaps = [&](auto&& query, const char* what, const EntryTable* k) {
            const std::size_t caps[] = {0, 1, want_total > 0 ? want_total - 1 : 0, want_total,
                                        want_total + 2};
            for (const std::size_t cap : caps) {
              std::vector<std::uint32_t> got(cap + 1, 0xabcdef);
              ASSERT_EQ(query(std::span(got.data(), cap)), want_total)
                  << what << " " << (k ? test::name_of(k) : "") << " cap " << cap;
              const std::size_t kept = std::min(cap, want_total);
              ASSERT_TRUE(std::equal(got.begin(), got.begin() + static_cast<std::ptrdiff_t>(kept),
                                     want_ids.begin()))
                  << what << " " << (k ? test::name_of(k) : "") << ", " << n << " spheres, cap "
                  << cap;
              ASSERT_EQ(got[kept], 0xabcdefu) << what << ": wrote past the list";
            }
          };
          auto check_nearest = [&](const Nearest& got, const char* what, const EntryTable* k) {
            ASSERT_TRUE(same_bits(got, want))
                << what << " " << (k ? test::name_of(k) : "") << ", " << n << " spheres: id "
                << got.id << " distance " << got.distance << ", reference id " << want.id
                << " distance " << want.distance;
          };
          check_nearest(nearest(v, p, max_distance), "dispatched", nullptr);
          check_overlaps([&](std::span<std::uint32_t> o) { return overlapping(v, p, radius, o); },
                         "dispatched", nullptr);
          const bool want_inside = scalar::overlapping(v, p, 0.0f, {}) > 0;
          EXPECT_EQ(inside(v, p), want_inside);
          for (std::size_t k = 0; k < kernels.size(); ++k) {
            const Hit kernel_best = kernels[k]->nearest(v, p, max_distance);
            const bool in_range = kernel_best.found() && kernel_best.t <= max_distance;
            ASSERT_EQ(in_range, want.found()) << test::name_of(kernels[k]);
            if (in_range) {
              ASSERT_EQ(kernel_best.id, want.id) << test::name_of(kernels[k]);
              ASSERT_TRUE(same_bits(kernel_best.t, want.distance)) << test::name_of(kernels[k]);
            }
            check_nearest(nearest(trees[k], p, max_distance), "tree", kernels[k]);
            check_overlaps(
                [&](std::span<std::uint32_t> o) { return overlapping(trees[k], p, radius, o); },
                "tree", kernels[k]);
            EXPECT_EQ(inside(trees[k], p), want_inside) << test::name_of(kernels[k]);
          }
        }
      });
  std::cout << "[ points ] " << queries << " queries (" << found << " nearest found, " << listed
            << " overlaps) bit for bit on every kernel and tree; " << decided_nearest
            << " nearest and " << decided_overlap << " overlap answers matched long double\n";
  EXPECT_GT(decided_nearest, queries * 3 / 4) << "too few decidable queries to bite";
  EXPECT_GT(decided_overlap, queries * 3 / 4) << "too few decidable queries to bite";
  EXPECT_GT(found, queries / 2);
  EXPECT_GT(listed, queries);
}

// The batch forms give each point the single query's answer.
TEST(PointQueries, BatchFormsAnswerEachPointAsTheSingleQuery) {
  std::mt19937 rng(161);
  const SphereSoA scene = test::make_scene(test::Shape::random, 300, rng);
  const SphereView v = scene.view();
  const SphereBVH tree(v);
  const std::vector<Vec3> points = points_for(v, 200, rng);
  std::vector<Nearest> near(points.size()), tree_near(points.size());
  auto in = std::make_unique<bool[]>(points.size());
  auto tree_in = std::make_unique<bool[]>(points.size());
  nearest(v, points, near, 2.0f);
  nearest(tree, points, tree_near, 2.0f);
  inside(v, points, std::span(in.get(), points.size()));
  inside(tree, points, std::span(tree_in.get(), points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Nearest one = nearest(v, points[i], 2.0f);
    ASSERT_TRUE(same_bits(near[i], one)) << i;
    ASSERT_TRUE(same_bits(tree_near[i], one)) << i;
    ASSERT_EQ(in[i], inside(v, points[i])) << i;
    ASSERT_EQ(tree_in[i], in[i]) << i;
  }
  EXPECT_THROW(nearest(tree, points, std::span(near).first(3)), std::length_error);
  EXPECT_THROW(inside(v, points, std::span(in.get(), 3)), std::length_error);
}

// The contract's pairs, one overlapping() query per valid sphere, higher ids kept; sorted.
std::vector<IdPair> reference_pairs(SphereView v) {
  std::vector<IdPair> pairs;
  std::vector<std::uint32_t> ids(v.count);
  for (std::size_t i = 0; i < v.count; ++i) {
    if (!valid(v, i)) continue;
    const std::size_t total = scalar::overlapping(v, {v.cx[i], v.cy[i], v.cz[i]}, v.radius[i], ids);
    for (std::size_t k = 0; k < total; ++k)
      if (ids[k] > i) pairs.push_back({static_cast<std::uint32_t>(i), ids[k]});
  }
  return pairs;
}

// All the pairs of a tree, found in `parts` shares and sorted.
std::vector<IdPair> pairs_in_parts(const SphereBVH& tree, std::size_t parts) {
  std::vector<IdPair> pairs;
  for (std::size_t part = 0; part < parts; ++part)
    overlapping_pairs(tree, pairs, part, parts);
  std::sort(pairs.begin(), pairs.end(), [](IdPair a, IdPair b) {
    return a.first != b.first ? a.first < b.first : a.second < b.second;
  });
  return pairs;
}

// Where |c_i - c_j| - r_i - r_j is clearly apart from 0 in long double, the pair is listed
// exactly when it is negative; every tree on every kernel, in one share or several, lists the
// reference's pairs, each once.
void check_pairs(SphereView v, const std::vector<SphereBVH>& trees,
                 const std::vector<const EntryTable*>& kernels, std::size_t& decided) {
  const std::vector<IdPair> want = reference_pairs(v);
  for (std::size_t i = 0; i < v.count; ++i) {
    if (!valid(v, i)) continue;
    const Vec3 c{v.cx[i], v.cy[i], v.cz[i]};
    for (std::size_t j = i + 1; j < v.count; ++j) {
      if (!valid(v, j)) continue;
      const L gap = distance(v, j, c) - v.radius[i];
      if (std::fabs(gap) <= slack(v, j, c) + 1e-4L * v.radius[i]) continue;
      ++decided;
      const IdPair pair{static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)};
      ASSERT_EQ(std::binary_search(want.begin(), want.end(), pair,
                                   [](IdPair a, IdPair b) {
                                     return a.first != b.first ? a.first < b.first
                                                               : a.second < b.second;
                                   }),
                gap < 0)
          << v.count << " spheres, pair " << i << " " << j;
    }
  }
  for (std::size_t k = 0; k < kernels.size(); ++k)
    for (const std::size_t parts : {1u, 3u, 64u})
      ASSERT_EQ(pairs_in_parts(trees[k], parts), want)
          << test::name_of(kernels[k]) << ", " << v.count << " spheres, " << parts << " parts";
}

TEST(PointQueries, OverlappingPairsAreTheReferencesPairsEachOnce) {
  std::mt19937 rng(162);
  const auto kernels = test::runnable_kernels();
  std::size_t scenes = 0, decided = 0, pairs = 0;
  test::for_each_query_scene(rng, kernels,
                             [&](SphereView v, const std::vector<SphereBVH>& trees, std::size_t n) {
                               // Nested and identical scenes of 3000 spheres have n^2 / 2 pairs:
                               // the next test walks trees that deep.
                               if (n >= 3000) return;
                               ++scenes;
                               pairs += reference_pairs(v).size();
                               check_pairs(v, trees, kernels, decided);
                             });
  std::cout << "[ pairs ] " << pairs << " pairs in " << scenes << " scenes alike on every tree; "
            << decided << " pairs decided against long double\n";
  EXPECT_GT(pairs, 1000u);
  EXPECT_GT(decided, 50000u);
}

// Spheres that touch to within a few units in the last place, far from the origin and near it:
// float's test decides each pair either way, and the walk's margin must not lose one that the
// test keeps.
TEST(PointQueries, OverlappingPairsKeepTouchingSpheresAsTheTestDecides) {
  std::mt19937 rng(163);
  const auto kernels = test::runnable_kernels();
  std::size_t listed = 0;
  for (const float offset : {0.0f, 1e4f, -3e6f}) {
    SphereSoA s;
    for (int k = 0; k < 1500; ++k) {
      const Vec3 c = Vec3{offset, offset, offset} + test::random_in_box(rng, 40.0f);
      const float r = test::uniform(rng, 0.01f, 1.0f), q = test::uniform(rng, 0.01f, 1.0f);
      // The second sphere r + q from the first, nudged by up to 4 units in the last place.
      const float nudge = 1.0f + static_cast<float>(static_cast<int>(rng() % 9) - 4) * 0x1p-23f;
      s.add(c, r);
      // Along an axis the two boxes only touch too; along another direction they overlap.
      const Vec3 axes[] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
      const Vec3 along = k % 2 == 0 ? axes[k / 2 % 3] : test::unit_vector(rng);
      s.add(c + (r + q) * nudge * along, q);
    }
    std::vector<SphereBVH> trees;
    for (const EntryTable* k : kernels)
      trees.emplace_back(s.view(), k->isa);
    const std::vector<IdPair> want = reference_pairs(s.view());
    listed += want.size();
    for (std::size_t k = 0; k < kernels.size(); ++k)
      ASSERT_EQ(pairs_in_parts(trees[k], 4), want) << test::name_of(kernels[k]) << " " << offset;
  }
  EXPECT_GT(listed, 1000u);  // about half of the touching pairs overlap in float
}

TEST(PointQueries, OverlappingPairsRefuseAPartBeyondTheParts) {
  SphereSoA s;
  s.add({0, 0, 0}, 1);
  const SphereBVH tree(s.view());
  std::vector<IdPair> pairs;
  EXPECT_THROW(overlapping_pairs(tree, pairs, 2, 2), std::invalid_argument);
  EXPECT_THROW(overlapping_pairs(tree, pairs, 0, 0), std::invalid_argument);
  EXPECT_TRUE(pairs.empty());
}

}  // namespace
}  // namespace sphray
