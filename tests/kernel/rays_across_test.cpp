// The stream with the rays across the lanes (brute/ray_lanes.hpp, QueryPlan::rays_across): on
// every instruction set this machine runs, its closest hits and occlusion answers equal, bit
// for bit, the scalar reference's and the same kernel's one ray at a time, on worked cases (ties,
// the open interval, rays from inside, tangents, every kind of invalid ray and sphere), on random
// scenes of 0 to 64 spheres with special values and masks, and at every stream length around the
// lane widths. The dispatched streams (views, ray arrays, small trees) too.
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>

#include "test_support.hpp"

namespace sphray {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

bool same_bits(const Hit& a, const Hit& b) {
  return a.id == b.id && std::memcmp(&a.t, &b.t, sizeof(float)) == 0;
}

// The same hit but for the sign of a zero t: where two spheres tie at t = 0, one at +0 and one
// at -0, the one-ray SIMD reduction keeps the lower id but may report the other's zero (left
// open: docs/robustness.md, "Not done"). The rays across the lanes keep the spheres in id order
// as the scalar reference does, and are held to its bits exactly.
bool same_but_zero_sign(const Hit& a, const Hit& b) {
  return same_bits(a, b) || (a.id == b.id && a.t == 0.0f && b.t == 0.0f);
}

std::string describe(const Ray& r, std::size_t i) {
  char text[256];
  std::snprintf(text, sizeof text, "ray %zu o (%a, %a, %a) d (%a, %a, %a) (%a, %a) mask %x", i,
                double(r.origin.x), double(r.origin.y), double(r.origin.z), double(r.dir.x),
                double(r.dir.y), double(r.dir.z), double(r.tmin), double(r.tmax), r.mask);
  return text;
}

std::string text(const Hit& h) {
  char out[64];
  std::snprintf(out, sizeof out, "id %u t %a", h.id, double(h.t));
  return out;
}

// Each kernel's rays-across streams against the scalar reference and the kernel's own per-ray
// queries, every ray of the stream. Returns the number of disagreements (each reported).
std::size_t check_kernel(const EntryTable& k, SphereView v, const std::vector<Ray>& rays) {
  const std::size_t n = rays.size();
  std::vector<Hit> across(n), streamed(n);
  auto blocked = std::make_unique<bool[]>(n + 1);
  auto blocked_stream = std::make_unique<bool[]>(n + 1);
  k.intersect_across(v, rays.data(), across.data(), n);
  k.intersect_stream(v, rays.data(), streamed.data(), n);
  k.occluded_across(v, rays.data(), blocked.get(), n);
  k.occluded_stream(v, rays.data(), blocked_stream.get(), n);
  std::size_t failures = 0;
  for (std::size_t i = 0; i < n && failures < 5; ++i) {
    const Hit ref = scalar::intersect(v, rays[i]);
    const bool ref_blocked = scalar::occluded(v, rays[i]);
    const Hit one = k.intersect(v, rays[i]);
    const bool ok = same_bits(across[i], ref) && same_but_zero_sign(one, ref) &&
                    same_but_zero_sign(streamed[i], ref) && blocked[i] == ref_blocked &&
                    k.occluded(v, rays[i]) == ref_blocked && blocked_stream[i] == ref_blocked;
    if (ok) continue;
    ++failures;
    ADD_FAILURE() << test::name_of(&k) << ", " << v.count << " spheres, " << n << " rays, "
                  << describe(rays[i], i) << ": scalar " << text(ref) << " blocked " << ref_blocked
                  << "; across " << text(across[i]) << " blocked " << blocked[i] << "; one ray "
                  << text(one) << "; stream " << text(streamed[i]) << " blocked "
                  << blocked_stream[i];
  }
  return failures;
}

// The public streams, which the query plan routes: views, ray arrays and a small tree.
void check_dispatched(SphereView v, const std::vector<Ray>& rays) {
  const std::size_t n = rays.size();
  std::vector<Hit> hits(n), column_hits(n);
  auto blocked = std::make_unique<bool[]>(n + 1);
  intersect(v, rays, hits);
  occluded(v, rays, std::span<bool>(blocked.get(), n));
  std::vector<float> o[3], d[3], tmin(n), tmax(n), t(n);
  std::vector<std::uint32_t> mask(n), id(n);
  for (int axis = 0; axis < 3; ++axis) {
    o[axis].resize(n);
    d[axis].resize(n);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Ray& r = rays[i];
    o[0][i] = r.origin.x, o[1][i] = r.origin.y, o[2][i] = r.origin.z;
    d[0][i] = r.dir.x, d[1][i] = r.dir.y, d[2][i] = r.dir.z;
    tmin[i] = r.tmin, tmax[i] = r.tmax, mask[i] = r.mask;
  }
  const RayArrays arrays{o[0].data(), o[1].data(), o[2].data(), d[0].data(), d[1].data(),
                         d[2].data(), tmin.data(), tmax.data(), mask.data(), n};
  intersect(v, arrays, HitArrays{t.data(), id.data(), n});
  for (std::size_t i = 0; i < n; ++i) {
    const Hit ref = scalar::intersect(v, rays[i]);
    EXPECT_TRUE(same_but_zero_sign(hits[i], ref))
        << v.count << " spheres, " << describe(rays[i], i);
    EXPECT_TRUE(same_but_zero_sign(Hit{t[i], id[i]}, ref)) << "arrays, " << describe(rays[i], i);
    EXPECT_EQ(blocked[i], scalar::occluded(v, rays[i])) << describe(rays[i], i);
  }
}

// A tree over few spheres is built flat and streams as brute force on them. Larger trees walk,
// and are checked elsewhere (their boxes reject the false hits at t = 0 of docs/robustness.md,
// "Not done", which brute force reports).
constexpr std::size_t kFlatTreeUpTo = 8;
void check_small_tree(const EntryTable& k, SphereView v, const std::vector<Ray>& rays) {
  if (v.count == 0 || v.count > kFlatTreeUpTo) return;
  const SphereBVH tree(v, k.isa);
  std::vector<Hit> hits(rays.size());
  auto blocked = std::make_unique<bool[]>(rays.size() + 1);
  intersect(tree, rays, hits);
  occluded(tree, rays, std::span<bool>(blocked.get(), rays.size()));
  for (std::size_t i = 0; i < rays.size(); ++i) {
    EXPECT_TRUE(same_but_zero_sign(hits[i], scalar::intersect(v, rays[i])))
        << test::name_of(&k) << " tree, " << describe(rays[i], i);
    EXPECT_EQ(blocked[i], scalar::occluded(v, rays[i])) << test::name_of(&k) << " tree";
  }
}

// Every length from 0 to twice the widest batch and a bit: every tail of a group of rays.
void check_every_length(SphereView v, const std::vector<Ray>& rays) {
  for (const EntryTable* k : test::runnable_kernels()) {
    for (std::size_t n = 0; n <= 37 && n <= rays.size(); ++n) {
      const std::vector<Ray> head(rays.begin(), rays.begin() + static_cast<std::ptrdiff_t>(n));
      ASSERT_EQ(check_kernel(*k, v, head), 0u) << "length " << n;
    }
  }
}

// Rays the contract rejects, and valid rays at its edges, towards a unit sphere at (0, 0, -3).
std::vector<Ray> worked_rays() {
  const Vec3 o{0, 0, 0}, z{0, 0, -1};
  std::vector<Ray> rays = {
      {o, z},                                     // hits at t = 2, ties between equal spheres
      {{0, 0, -3}, z},                            // from the centre: the far side, t = 1
      {{0, 1, 0}, z},                             // tangent
      {{0, 1.0001f, 0}, z},                       // just outside
      {o, z, 2.0f, kInf},                         // tmin at the near root: the far one, t = 4
      {o, z, 0.0f, 2.0f},                         // tmax at the near root: open, a miss
      {o, z, 2.0f, 4.0f},                         // both roots at the ends: a miss
      {o, {0, 0, 1}},                             // away from it
      {o, {0, 0, 0}},                             // zero direction
      {o, {1e-30f, 0, 0}},                        // |dir|^2 underflows
      {o, {0, 0, -1e20f}},                        // |dir|^2 overflows
      {{kNaN, 0, 0}, z},                          // NaN origin
      {o, {0, kInf, -1}},                         // infinite direction
      {o, z, 1.0f, 1.0f},                         // empty interval
      {o, z, kNaN, kInf},                         // NaN tmin
      {o, z, 0.0f, kNaN},                         // NaN tmax
      {o, z, -kInf, kInf},                        // the whole line
      {o, z, 0.0f, kInf, 0u},                     // mask 0: sees nothing
      {o, z, 0.0f, kInf, 0x2u},                   // sees the spheres of bit 1 only
      {{0, 0, 10}, {0, 0, -1e-3f}},               // short direction, far away
      {{0.5f, 0.5f, -3}, {1, 1, 0}, -kInf, kInf}  // from inside, both ways
  };
  return rays;
}

// The unit sphere at (0, 0, -3) among invalid and edge-case spheres, twice (a tie at equal t,
// the lower id wins), and a sphere behind it.
SphereSoA worked_spheres() {
  SphereSoA s;
  s.add({0, 0, -3}, kNaN, 0x1u);                            // NaN radius
  s.add({kNaN, 0, -3}, 1.0f, 0x1u);                         // NaN centre
  s.add({0, kInf, -3}, 1.0f, 0x1u);                         // infinite centre
  s.add({0, 0, -3}, 0.0f, 0x1u);                            // radius 0
  s.add({0, 0, -3}, -1.0f, 0x1u);                           // negative radius
  s.add({0, 0, -3}, 1e-45f, 0x1u);                          // denormal radius
  s.add({0, 0, -3}, std::nextafter(0x1p-63f, 0.0f), 0x1u);  // just below the smallest valid
  s.add({0, 0, -3}, 0x1p64f, 0x1u);                         // just above the largest valid
  s.add({0, 0, -3}, 1.0f, 0x2u);                            // id 8: the sphere
  s.add({0, 0, -3}, 1.0f, 0x3u);                            // id 9: the same, a tie
  s.add({0, 0, -6}, 1.0f, 0x2u);                            // behind
  s.add({0, 0, -3}, 0x1p-63f, 0x1u);                        // the smallest valid radius
  return s;
}

TEST(RaysAcross, WorkedCasesAtEveryLength) {
  const SphereSoA spheres = worked_spheres();
  std::vector<Ray> rays;
  while (rays.size() < 40) {  // every case at every lane position
    const auto more = worked_rays();
    rays.insert(rays.end(), more.begin(),
                more.end() - static_cast<std::ptrdiff_t>(rays.size() % 3));
  }
  SphereView masked = spheres.view();
  SphereView unmasked = masked;
  unmasked.mask = nullptr;
  check_every_length(masked, rays);
  check_every_length(unmasked, rays);
  check_dispatched(masked, rays);
  check_dispatched(unmasked, rays);
  const Hit centre = scalar::intersect(unmasked, rays[0]);
  EXPECT_EQ(centre.id, 8u);
  EXPECT_EQ(centre.t, 2.0f);
}

// A field: usually ordinary, sometimes at an edge of float or of the contract.
float field(std::mt19937& rng, float lo, float hi) {
  static const float kEdges[] = {0.0f,  -0.0f,   1e-45f, FLT_MIN, 0x1p-63f, 1e-10f, 1e10f,
                                 1e19f, 0x1p64f, 1e30f,  FLT_MAX, kInf,     -kInf,  kNaN};
  if (rng() % 12 == 0) return kEdges[rng() % (sizeof kEdges / sizeof kEdges[0])];
  return test::uniform(rng, lo, hi);
}

test::LooseSpheres random_spheres(std::mt19937& rng, std::size_t n) {
  test::LooseSpheres s;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 c{field(rng, -6, 6), field(rng, -6, 6), field(rng, -6, 6)};
    s.add(c, field(rng, 0.2f, 3.0f));
  }
  return s;
}

std::vector<Ray> random_rays(std::mt19937& rng, std::size_t n) {
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    r.origin = {field(rng, -8, 8), field(rng, -8, 8), field(rng, -8, 8)};
    r.dir = {field(rng, -1, 1), field(rng, -1, 1), field(rng, -1, 1)};
    if (rng() % 8 == 0) r.tmin = field(rng, -2, 2);
    if (rng() % 8 == 0) r.tmax = field(rng, 0, 10);
    r.mask = rng() % 4 == 0 ? static_cast<std::uint32_t>(rng() % 8) : kAllBits;
  }
  return rays;
}

// Random masks on the spheres of s, from a few bits, so that rays see some of them.
std::vector<std::uint32_t> random_masks(std::mt19937& rng, std::size_t n) {
  std::vector<std::uint32_t> masks(n);
  for (auto& m : masks)
    m = static_cast<std::uint32_t>(rng() % 8);
  return masks;
}

TEST(RaysAcross, RandomScenesWithSpecialValuesAgreeBitForBit) {
  std::mt19937 rng(33);
  for (std::size_t spheres = 0; spheres <= 64; spheres += spheres < 40 ? 1 : 12) {
    const test::LooseSpheres s = random_spheres(rng, spheres);
    const std::vector<Ray> rays = random_rays(rng, test::scaled(4000) + 5);
    const std::vector<std::uint32_t> masks = random_masks(rng, spheres);
    SphereView masked = s.view();
    masked.mask = masks.data();
    for (const SphereView v : {s.view(), masked}) {
      for (const EntryTable* k : test::runnable_kernels()) {
        ASSERT_EQ(check_kernel(*k, v, rays), 0u);
        check_small_tree(*k, v, rays);
      }
      check_dispatched(v, rays);
    }
  }
}

// Random ordinary scenes, ordinary rays: most rays hit something, and a tail of every length.
TEST(RaysAcross, OrdinaryScenesAtEveryLength) {
  std::mt19937 rng(8);
  for (std::size_t spheres : {1u, 2u, 3u, 5u, 8u, 16u, 33u}) {
    SphereSoA s;
    test::fill_random(s, spheres, rng);
    check_every_length(s.view(), test::random_rays(40, rng));
  }
}

}  // namespace
}  // namespace sphray
