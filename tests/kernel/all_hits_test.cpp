// intersect_all and count_hits (all_hits.hpp): every crossing of a ray with the spheres, against
// a long-double reference written here, on scenes of many shapes; every kernel, the dispatched
// queries, the trees and the scalar reference bit for bit alike; capacities smaller than the
// number of crossings; and the contract's invalid input.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <tuple>

#include "test_support.hpp"

namespace sphray {
namespace {

struct Crossing {
  long double t;
  std::uint32_t id;
  bool exit;
};

// The reference: each sphere's roots in long double, k -+ sqrt(disc / a) with k = g.d / a and
// disc = r^2 - |k d - g|^2 (64 bits of mantissa: float's rounding of the same formula is far
// below what separates the decidable cases). A ray is undecidable, and left out, where float
// cannot be expected to agree: a discriminant within rounding of 0 (a grazing ray), a root
// within rounding of tmin or tmax, or two crossings of different spheres within rounding of
// each other (their order).
struct Reference {
  std::vector<Crossing> crossings;
  bool decidable = true;
};

Reference reference(SphereView v, const Ray& ray) {
  Reference ref;
  using L = long double;
  const L ox = ray.origin.x, oy = ray.origin.y, oz = ray.origin.z;
  const L dx = ray.dir.x, dy = ray.dir.y, dz = ray.dir.z;
  const L a = dx * dx + dy * dy + dz * dz;
  const L scale_t = std::sqrt(ox * ox + oy * oy + oz * oz) / std::sqrt(a) + 1;
  constexpr L kRel = 1e-4L;
  for (std::size_t i = 0; i < v.count; ++i) {
    const L cx = v.cx[i], cy = v.cy[i], cz = v.cz[i], r = v.radius[i];
    if (!(std::isfinite(cx) && std::isfinite(cy) && std::isfinite(cz) && std::isfinite(r)) ||
        !(r > 0))
      continue;
    const L gx = cx - ox, gy = cy - oy, gz = cz - oz;
    const L k = (gx * dx + gy * dy + gz * dz) / a;
    const L px = k * dx - gx, py = k * dy - gy, pz = k * dz - gz;
    const L disc = r * r - (px * px + py * py + pz * pz);
    const L g2 = gx * gx + gy * gy + gz * gz;
    if (std::fabs(disc) <= kRel * (r * r + g2)) {
      ref.decidable = false;
      continue;
    }
    if (disc < 0) continue;
    const L half = std::sqrt(disc / a);
    const L roots[2] = {k - half, k + half};
    for (int exit = 0; exit < 2; ++exit) {
      const L t = roots[exit];
      const L margin = kRel * (scale_t + std::sqrt(g2 / a) + r / std::sqrt(a));
      if (std::fabs(t - ray.tmin) <= margin ||
          (std::isfinite(ray.tmax) && std::fabs(t - ray.tmax) <= margin)) {
        ref.decidable = false;
      }
      if (t > ray.tmin && t < ray.tmax)
        ref.crossings.push_back({t, static_cast<std::uint32_t>(i), exit == 1});
    }
  }
  std::sort(ref.crossings.begin(), ref.crossings.end(), [](const Crossing& x, const Crossing& y) {
    return std::tie(x.t, x.id, x.exit) < std::tie(y.t, y.id, y.exit);
  });
  for (std::size_t i = 1; i < ref.crossings.size(); ++i) {
    const Crossing& p = ref.crossings[i - 1];
    const Crossing& q = ref.crossings[i];
    if (p.id != q.id && p.t != q.t && q.t - p.t <= kRel * (std::fabs(q.t) + scale_t))
      ref.decidable = false;
  }
  return ref;
}

bool same_bits(const Hit& a, const Hit& b) {
  return a.id == b.id && std::memcmp(&a.t, &b.t, sizeof(float)) == 0;
}

// Random rays from in and around the scenes (many start inside spheres); every third with a
// finite random interval.
std::vector<Ray> rays_for(std::size_t n, std::mt19937& rng) {
  std::vector<Ray> rays = test::random_rays(n, rng);
  for (std::size_t i = 0; i < n; i += 3) {
    rays[i].tmin = test::uniform(rng, -5.0f, 2.0f);
    rays[i].tmax = rays[i].tmin + test::uniform(rng, 0.5f, 20.0f);
  }
  return rays;
}

TEST(AllHits, WorkedCaseNestedAndInside) {
  SphereSoA s;
  s.add({0, 0, 5}, 1.0f);  // id 0: entered at 4, left at 6
  s.add({0, 0, 5}, 2.0f);  // id 1: entered at 3, left at 7
  s.add({0, 0, 0}, 3.0f);  // id 2: the ray starts inside, leaves at 3
  const Ray ray{{0, 0, 0}, {0, 0, 1}};
  Hit out[5];
  bool exits[5];
  ASSERT_EQ(intersect_all(s.view(), ray, out, exits), 5u);
  const Hit want[] = {{3, 1}, {3, 2}, {4, 0}, {6, 0}, {7, 1}};
  const bool want_exit[] = {false, true, false, true, true};
  for (int i = 0; i < 5; ++i) {
    EXPECT_TRUE(same_bits(out[i], want[i])) << i << ": t " << out[i].t << " id " << out[i].id;
    EXPECT_EQ(exits[i], want_exit[i]) << i;
  }
  EXPECT_EQ(count_hits(s.view(), ray), 5u);
  // The interval is open at both ends: tmin = 3 and tmax = 7 leave out the crossings there.
  const Ray inner{{0, 0, 0}, {0, 0, 1}, 3.0f, 7.0f};
  EXPECT_EQ(count_hits(s.view(), inner), 2u);
}

TEST(AllHits, TangentRayEntersAndLeavesAtOnePoint) {
  SphereSoA s;
  s.add({0, 1, 5}, 1.0f);  // the line y = 0 touches it at z = 5
  Hit out[2];
  bool exits[2];
  ASSERT_EQ(intersect_all(s.view(), Ray{{0, 0, 0}, {0, 0, 1}}, out, exits), 2u);
  EXPECT_TRUE(same_bits(out[0], out[1]));
  EXPECT_EQ(out[0].t, 5.0f);
  EXPECT_FALSE(exits[0]);
  EXPECT_TRUE(exits[1]);
}

TEST(AllHits, InvalidInputHasNoCrossingsAndLeavesTheOutputAlone) {
  SphereSoA s;
  s.add({0, 0, 5}, 1.0f);
  s.add({0, 0, 9}, NAN);
  s.add({0, NAN, 12}, 1.0f);
  s.add({0, 0, 15}, -1.0f);
  s.add({0, 0, 18}, 0.0f);
  const Ray good{{0, 0, 0}, {0, 0, 1}};
  EXPECT_EQ(count_hits(s.view(), good), 2u);  // the valid sphere only
  const Ray bad[] = {{{NAN, 0, 0}, {0, 0, 1}},      {{0, 0, 0}, {0, 0, 0}},
                     {{0, 0, 0}, {0, INFINITY, 1}}, {{0, 0, 0}, {0, 0, 1}, 5.0f, 5.0f},
                     {{0, 0, 0}, {0, 0, 1}, NAN},   {{0, 0, 0}, {0, 0, 1}, 0.0f, NAN}};
  const SphereBVH tree(s.view());
  for (const Ray& ray : bad) {
    Hit out[2] = {{-1, 7}, {-1, 7}};
    EXPECT_EQ(intersect_all(s.view(), ray, out), 0u);
    EXPECT_EQ(intersect_all(tree, ray, out), 0u);
    EXPECT_EQ(count_hits(tree, ray), 0u);
    EXPECT_EQ(scalar::intersect_all(s.view(), ray, out, {}), 0u);
    EXPECT_TRUE(same_bits(out[0], Hit{-1, 7}) && same_bits(out[1], Hit{-1, 7}));
  }
  Hit out[2];
  bool exits[1];
  EXPECT_THROW(intersect_all(s.view(), good, out, exits), std::length_error);
  EXPECT_THROW(intersect_all(tree, good, out, exits), std::length_error);
}

// The full list of every kernel and tree equals the scalar reference's bit for bit, its first
// crossing is the closest hit, any capacity gets the list's first elements and the same total,
// and decidable rays match the long-double reference.
TEST(AllHits, EveryKernelAndTreeMatchTheReferences) {
  std::mt19937 rng(15);
  const auto kernels = test::runnable_kernels();
  std::size_t rays_checked = 0, decided = 0, crossings_seen = 0, capped = 0;
  test::for_each_query_scene(
      rng, kernels, [&](SphereView v, const std::vector<SphereBVH>& trees, std::size_t n) {
        for (const Ray& ray : rays_for(test::scaled(n >= 3000 ? 60 : 200), rng)) {
          ++rays_checked;
          const std::size_t total = scalar::intersect_all(v, ray, {}, {});
          std::vector<Hit> want(total);
          std::vector<char> want_exit(total);
          {
            auto flags = std::make_unique<bool[]>(total + 1);
            ASSERT_EQ(scalar::intersect_all(v, ray, want, std::span(flags.get(), total)), total);
            for (std::size_t i = 0; i < total; ++i)
              want_exit[i] = flags[i];
          }
          crossings_seen += total;
          // The first crossing is the closest hit.
          const Hit closest = scalar::intersect(v, ray);
          if (total == 0) {
            EXPECT_FALSE(closest.found());
          } else {
            EXPECT_TRUE(same_bits(want[0], closest))
                << "first crossing t " << want[0].t << " id " << want[0].id << ", closest t "
                << closest.t << " id " << closest.id;
          }
          // The long-double reference, where float can decide.
          const Reference ref = reference(v, ray);
          if (ref.decidable) {
            ++decided;
            ASSERT_EQ(total, ref.crossings.size()) << n << " spheres";
            for (std::size_t i = 0; i < total; ++i) {
              const Crossing& c = ref.crossings[i];
              EXPECT_EQ(want[i].id, c.id) << i;
              EXPECT_EQ(want_exit[i] != 0, c.exit) << i;
              EXPECT_NEAR(want[i].t, static_cast<double>(c.t), 1e-4 * (std::fabs(c.t) + 30)) << i;
            }
          }
          // Every kernel, the dispatched query and every tree, whole and capped; the nearest
          // crossings alone return how many they wrote instead of the total.
          auto check = [&](auto&& query, const char* what, const EntryTable* k,
                           bool nearest = false) {
            const std::size_t caps[] = {0, 1, 2, total > 0 ? total - 1 : 0, total, total + 3};
            for (const std::size_t cap : caps) {
              std::vector<Hit> got(cap + 1, Hit{-1, 12345});
              auto flags = std::make_unique<bool[]>(cap + 1);
              const std::size_t n_got =
                  query(std::span(got.data(), cap), std::span(flags.get(), cap));
              const std::size_t kept = std::min(cap, total);
              ASSERT_EQ(n_got, nearest ? kept : total)
                  << what << " " << (k ? test::name_of(k) : "") << " cap " << cap;
              capped += cap < total;
              for (std::size_t i = 0; i < kept; ++i) {
                ASSERT_TRUE(same_bits(got[i], want[i]) && flags[i] == (want_exit[i] != 0))
                    << what << " " << (k ? test::name_of(k) : "") << ", " << n << " spheres, cap "
                    << cap << ", crossing " << i << ": t " << got[i].t << " id " << got[i].id
                    << ", reference t " << want[i].t << " id " << want[i].id;
              }
              for (std::size_t i = kept; i <= cap; ++i)
                ASSERT_TRUE(same_bits(got[i], Hit{-1, 12345})) << what << ": wrote past the list";
            }
          };
          check([&](std::span<Hit> o, std::span<bool> e) { return intersect_all(v, ray, o, e); },
                "dispatched", nullptr);
          EXPECT_EQ(count_hits(v, ray), total);
          check(
              [&](std::span<Hit> o, std::span<bool> e) { return intersect_nearest(v, ray, o, e); },
              "nearest", nullptr, true);
          for (std::size_t k = 0; k < kernels.size(); ++k) {
            check(
                [&](std::span<Hit> o, std::span<bool> e) {
                  return kernels[k]->intersect_all(v, ray, o.data(), e.data(), o.size());
                },
                "kernel", kernels[k]);
            check([&](std::span<Hit> o,
                      std::span<bool> e) { return intersect_all(trees[k], ray, o, e); },
                  "tree", kernels[k]);
            EXPECT_EQ(count_hits(trees[k], ray), total);
            check([&](std::span<Hit> o,
                      std::span<bool> e) { return intersect_nearest(trees[k], ray, o, e); },
                  "tree nearest", kernels[k], true);
            // Without exit flags the nearest crossing alone is the closest hit's walk.
            for (const std::size_t cap : {std::size_t{1}, std::size_t{2}}) {
              std::vector<Hit> got(cap, Hit{-1, 12345});
              const std::size_t n_got = intersect_nearest(trees[k], ray, got);
              ASSERT_EQ(n_got, std::min(cap, total)) << test::name_of(kernels[k]) << " cap " << cap;
              for (std::size_t i = 0; i < cap; ++i)
                ASSERT_TRUE(same_bits(got[i], i < n_got ? want[i] : Hit{-1, 12345}))
                    << test::name_of(kernels[k]) << " cap " << cap << ", crossing " << i;
            }
          }
        }
      });
  std::cout << "[ crossings ] " << rays_checked << " rays, " << crossings_seen
            << " crossings, bit for bit on every kernel and tree; " << decided
            << " rays matched against long double; " << capped << " capped lists\n";
  EXPECT_GT(decided, rays_checked * 3 / 4) << "too few decidable rays for the reference to bite";
  EXPECT_GT(crossings_seen, rays_checked) << "too few crossings for the comparison to bite";
}

// The batch forms give each ray the single query's answer, in its own slots.
TEST(AllHits, BatchFormsAnswerEachRayAsTheSingleQuery) {
  std::mt19937 rng(151);
  const SphereSoA scene = test::make_scene(test::Shape::clustered, 300, rng);
  const SphereView v = scene.view();
  const SphereBVH tree(v);
  const std::vector<Ray> rays = rays_for(200, rng);
  constexpr std::size_t kPer = 3;
  std::vector<std::size_t> counts(rays.size()), tree_counts(rays.size()), only(rays.size());
  std::vector<Hit> out(rays.size() * kPer, Hit{-1, 9}), tree_out(out);
  intersect_all(v, rays, out, kPer, counts);
  intersect_all(tree, rays, tree_out, kPer, tree_counts);
  count_hits(tree, rays, only);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    Hit one[kPer] = {{-1, 9}, {-1, 9}, {-1, 9}};
    const std::size_t n = intersect_all(v, rays[i], one);
    ASSERT_EQ(counts[i], n);
    ASSERT_EQ(tree_counts[i], n);
    ASSERT_EQ(only[i], n);
    for (std::size_t k = 0; k < kPer; ++k) {
      ASSERT_TRUE(same_bits(out[i * kPer + k], one[k])) << "ray " << i << " slot " << k;
      ASSERT_TRUE(same_bits(tree_out[i * kPer + k], one[k])) << "ray " << i << " slot " << k;
    }
  }
  // The nearest crossings alone: the same slots, how many written in place of the total.
  std::vector<Hit> near_out(out.size(), Hit{-1, 9}), tree_near_out(out.size(), Hit{-1, 9});
  std::vector<std::size_t> near_counts(rays.size()), tree_near_counts(rays.size());
  intersect_nearest(v, rays, near_out, kPer, near_counts);
  intersect_nearest(tree, rays, tree_near_out, kPer, tree_near_counts);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(near_counts[i], std::min(counts[i], kPer)) << "ray " << i;
    ASSERT_EQ(tree_near_counts[i], near_counts[i]) << "ray " << i;
    for (std::size_t k = 0; k < kPer; ++k) {
      ASSERT_TRUE(same_bits(near_out[i * kPer + k], out[i * kPer + k])) << "ray " << i;
      ASSERT_TRUE(same_bits(tree_near_out[i * kPer + k], out[i * kPer + k])) << "ray " << i;
    }
  }
  EXPECT_THROW(intersect_nearest(tree, rays, std::span(out).first(1), kPer, counts),
               std::length_error);
  std::vector<std::size_t> short_counts(rays.size() - 1);
  EXPECT_THROW(count_hits(v, rays, short_counts), std::length_error);
  EXPECT_THROW(intersect_all(tree, rays, std::span(out).first(out.size() - 1), kPer, counts),
               std::length_error);
  EXPECT_THROW(intersect_all(v, rays, out, 0, counts), std::length_error);
}

}  // namespace
}  // namespace sphray
