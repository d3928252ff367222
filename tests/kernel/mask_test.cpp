// Ray and sphere masks (Ray::mask, SphereView::mask): a ray sees a sphere only if their masks
// share a bit. The oracle is independent of the masked code: the same query, unmasked, on a
// view holding only the spheres the ray's mask sees (in id order, so ties still go to the lower
// id), its ids mapped back. Every kernel, the dispatched queries, the streams, the every-hit
// queries and the trees must give exactly that.
#include <cstring>

#include "test_support.hpp"

namespace sphray {
namespace {

bool same_bits(const Hit& a, const Hit& b) {
  return a.id == b.id && std::memcmp(&a.t, &b.t, sizeof(float)) == 0;
}

// The spheres of v that rays with mask see, and their ids in v.
struct Visible {
  SphereSoA spheres;
  std::vector<std::uint32_t> ids;

  Visible(SphereView v, std::uint32_t ray_mask) {
    for (std::size_t i = 0; i < v.count; ++i) {
      if ((v.mask[i] & ray_mask) == 0) continue;
      spheres.add({v.cx[i], v.cy[i], v.cz[i]}, v.radius[i]);
      ids.push_back(static_cast<std::uint32_t>(i));
    }
  }
  Hit in_view(Hit h) const { return h.found() ? Hit{h.t, ids[h.id]} : h; }
};

TEST(Masks, SphereSoAKeepsNoMaskArrayUntilOneIsSet) {
  SphereSoA s;
  s.add({0, 0, 0}, 1.0f);
  s.add({0, 0, 5}, 1.0f, kAllBits);
  EXPECT_EQ(s.view().mask, nullptr);
  EXPECT_EQ(s.mask(1), kAllBits);
  s.add({0, 0, 9}, 1.0f, 0x4u);
  ASSERT_NE(s.view().mask, nullptr);
  EXPECT_EQ(s.mask(0), kAllBits);
  EXPECT_EQ(s.mask(2), 0x4u);
  s.set_mask(0, 0x2u);
  EXPECT_EQ(s.view().mask[0], 0x2u);
  EXPECT_THROW(s.set_mask(3, 1u), std::out_of_range);
  for (int i = 0; i < 40; ++i)  // grows past the first capacity: the masks move along
    s.add({0, 0, 20.0f + static_cast<float>(i)}, 0.5f);
  EXPECT_EQ(s.mask(0), 0x2u);
  EXPECT_EQ(s.mask(2), 0x4u);
  EXPECT_EQ(s.mask(42), kAllBits);
  const SphereSoA copy = s;
  EXPECT_EQ(copy.mask(2), 0x4u);
}

TEST(Masks, WorkedCase) {
  SphereSoA s;
  s.add({0, 0, 5}, 1.0f, 0x1u);   // id 0, nearest
  s.add({0, 0, 10}, 1.0f, 0x2u);  // id 1
  const SphereView v = s.view();
  const SphereBVH tree(v);
  Ray ray{{0, 0, 0}, {0, 0, 1}};
  EXPECT_EQ(intersect(v, ray).id, 0u);
  ray.mask = 0x2u;
  EXPECT_EQ(intersect(v, ray).id, 1u);
  EXPECT_EQ(intersect(tree, ray).id, 1u);
  EXPECT_EQ(count_hits(v, ray), 2u);
  ray.mask = 0x4u;
  EXPECT_FALSE(intersect(v, ray).found());
  EXPECT_FALSE(occluded(tree, ray));
  ray.mask = 0;  // sees nothing, even spheres without masks
  SphereSoA plain;
  plain.add({0, 0, 5}, 1.0f);
  EXPECT_FALSE(intersect(plain.view(), ray).found());
  EXPECT_FALSE(scalar::intersect(plain.view(), ray).found());
  // Refit reads the masks again.
  SphereSoA moved = s;
  moved.set_mask(1, 0x4u);
  SphereBVH refitted(v);
  refitted.refit(moved.view());
  EXPECT_EQ(intersect(refitted, ray).id, kNoHit);
  ray.mask = 0x4u;
  EXPECT_EQ(intersect(refitted, ray).id, 1u);
}

TEST(Masks, EveryKernelAndTreeMatchTheVisibleSpheresAlone) {
  std::mt19937 rng(17);
  const auto kernels = test::runnable_kernels();
  // Masks that hide nothing, everything, half, one bit, and random ones.
  const std::uint32_t ray_masks[] = {kAllBits, 0u, 0x55555555u, 0x1u, 0x80000000u, 0x0f0f0000u};
  std::size_t compared = 0, traced = 0, hits = 0, hidden = 0;
  test::for_each_query_scene(
      rng, {}, [&](SphereView plain, const std::vector<SphereBVH>&, std::size_t n) {
        // Sphere masks: every bit, none, one bit each, and random words.
        std::vector<std::uint32_t> masks(n + 16, 0u);
        for (std::size_t i = 0; i < n; ++i) {
          const std::uint32_t kinds[] = {kAllBits, 0u, 1u << (rng() % 32),
                                         static_cast<std::uint32_t>(rng())};
          masks[i] = kinds[rng() % 4];
        }
        SphereView v = plain;
        v.mask = masks.data();
        std::vector<SphereBVH> trees;
        for (const EntryTable* k : kernels)
          trees.emplace_back(v, k->isa);
        std::vector<Ray> rays = test::random_rays(test::scaled(n >= 3000 ? 60 : 150), rng);
        for (const std::uint32_t ray_mask : ray_masks) {
          const Visible visible(v, ray_mask);
          const SphereView seen = visible.spheres.view();
          hidden += n - visible.ids.size();
          for (Ray& r : rays)
            r.mask = ray_mask;
          std::vector<Hit> want(rays.size());
          for (std::size_t i = 0; i < rays.size(); ++i) {
            Ray unmasked = rays[i];
            unmasked.mask = kAllBits;
            want[i] = visible.in_view(scalar::intersect(seen, unmasked));
            hits += want[i].found();
            ++traced;
          }
          auto check = [&](const char* what, const EntryTable* k, auto&& closest, auto&& blocked,
                           auto&& count) {
            for (std::size_t i = 0; i < rays.size(); ++i) {
              ++compared;
              Ray unmasked = rays[i];
              unmasked.mask = kAllBits;
              const Hit got = closest(rays[i]);
              ASSERT_TRUE(same_bits(got, want[i]))
                  << what << " " << (k ? test::name_of(k) : "") << ", " << n << " spheres, mask "
                  << ray_mask << ": id " << got.id << " t " << got.t << ", want id " << want[i].id
                  << " t " << want[i].t;
              ASSERT_EQ(blocked(rays[i]), scalar::occluded(seen, unmasked)) << what;
              ASSERT_EQ(count(rays[i]), count_hits(seen, unmasked)) << what;
            }
          };
          check(
              "scalar", nullptr, [&](const Ray& r) { return scalar::intersect(v, r); },
              [&](const Ray& r) { return scalar::occluded(v, r); },
              [&](const Ray& r) { return scalar::intersect_all(v, r, {}, {}); });
          check(
              "dispatched", nullptr, [&](const Ray& r) { return intersect(v, r); },
              [&](const Ray& r) { return occluded(v, r); },
              [&](const Ray& r) { return count_hits(v, r); });
          // The same spheres read as a view without padding, its masks exactly n long: the
          // kernels then load the last, partial batch of spheres and masks on their own.
          const std::vector<std::uint32_t> exact_masks(masks.begin(), masks.begin() + n);
          SphereView unpadded = v;
          unpadded.padded_count = 0;
          unpadded.mask = exact_masks.data();
          for (std::size_t k = 0; k < kernels.size(); ++k) {
            const EntryTable* e = kernels[k];
            check(
                "kernel", e, [&](const Ray& r) { return e->intersect(v, r); },
                [&](const Ray& r) { return e->occluded(v, r); },
                [&](const Ray& r) { return e->intersect_all(v, r, nullptr, nullptr, 0); });
            check(
                "kernel, unpadded view", e, [&](const Ray& r) { return e->intersect(unpadded, r); },
                [&](const Ray& r) { return e->occluded(unpadded, r); },
                [&](const Ray& r) { return e->intersect_all(unpadded, r, nullptr, nullptr, 0); });
            check(
                "tree", e, [&](const Ray& r) { return intersect(trees[k], r); },
                [&](const Ray& r) { return occluded(trees[k], r); },
                [&](const Ray& r) { return count_hits(trees[k], r); });
            // The streams, brute force and tree.
            std::vector<Hit> got(rays.size()), got_tree(rays.size());
            e->intersect_stream(v, rays.data(), got.data(), rays.size());
            intersect(trees[k], rays, got_tree);
            for (std::size_t i = 0; i < rays.size(); ++i) {
              ASSERT_TRUE(same_bits(got[i], want[i]))
                  << "stream " << test::name_of(e) << " ray " << i;
              ASSERT_TRUE(same_bits(got_tree[i], want[i]))
                  << "tree stream " << test::name_of(e) << " ray " << i;
            }
          }
        }
      });
  std::cout << "[ masks ] " << traced << " rays, " << compared
            << " answers like the visible spheres' alone (" << hits << " hits, " << hidden
            << " spheres hidden)\n";
  EXPECT_GT(hits, traced / 20) << "too few hits for the comparison to bite";
}

}  // namespace
}  // namespace sphray
