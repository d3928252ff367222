// Rays that start on a sphere and leave it (nearly) tangentially, as a tracer's secondary rays
// do: every reported hit must lie on its sphere within the bound of docs/kernel.md ("Where a hit
// can lie"), never beyond the chord, every instruction set must return the same bits, and where
// a long-double reference can decide hit or miss beyond rounding, every one must decide alike.
#include <array>
#include <cmath>
#include <iostream>

#include "test_support.hpp"

namespace sphray {
namespace {

using Real = long double;
constexpr Real kU = 0x1p-24L;  // float's unit roundoff

// docs/kernel.md: a hit's point o + t d lies within kPointBound u (r + |c - o|) of the sphere.
constexpr Real kPointBound = 16;

struct Exact {
  Real g;                // |c - o|
  Real dir;              // |d|
  bool hit;              // the selected root lies in (tmin, tmax)
  bool within_rounding;  // grazing, or a root within rounding of tmin: float may decide either way
};

// The roots of |o + t d - c| = r in long double on the same float inputs, and whether float
// arithmetic could be expected to decide them: the discriminant or a root within a band of
// kBand u of the problem's scale.
Exact reference(Vec3 c, float r, const Ray& ray) {
  constexpr Real kBand = 64;
  const Real gx = Real(c.x) - ray.origin.x, gy = Real(c.y) - ray.origin.y,
             gz = Real(c.z) - ray.origin.z;
  const Real dx = ray.dir.x, dy = ray.dir.y, dz = ray.dir.z;
  const Real a = dx * dx + dy * dy + dz * dz, b = gx * dx + gy * dy + gz * dz;
  const Real k = b / a, vx = k * dx - gx, vy = k * dy - gy, vz = k * dz - gz;
  const Real rr = r, g = std::sqrt(gx * gx + gy * gy + gz * gz);
  const Real disc = rr * rr - (vx * vx + vy * vy + vz * vz);  // r^2 - closest approach^2
  const Real scale = rr + g;
  Exact e{g, std::sqrt(a), false, std::abs(disc) <= kBand * kU * scale * rr};
  if (disc < 0) return e;
  // Vieta's form, with c = |g|^2 - r^2 from the inputs (nearly exact in long double), so that
  // a root at the origin comes out as 0, not as the rounding of k - h.
  const Real q = b + std::copysign(std::sqrt(a * disc), b);
  const Real c0 = (gx * gx + gy * gy + gz * gz) - rr * rr;
  const Real ta = c0 / q, tb = q / a;
  const Real t0 = std::min(ta, tb), t1 = std::max(ta, tb), tmin = ray.tmin;
  const Real band = kBand * kU * (scale / e.dir + std::abs(tmin));
  e.within_rounding |= std::abs(t0 - tmin) <= band || std::abs(t1 - tmin) <= band;
  const Real t = t0 > tmin ? t0 : t1;
  e.hit = t > tmin && t < Real(ray.tmax);
  return e;
}

struct Counts {
  std::size_t rays = 0, hits = 0, off_sphere = 0, beyond_chord = 0, undecided = 0,
              wrong_decision = 0, isa_mismatch = 0, bvh_mismatch = 0;
  Real worst_point = 0;  // the largest | |p - c| - r | / (u (r + |c - o|)) seen
};

// Checks a hit of sphere (c, r) against the point bound and the chord.
void check_point(Vec3 c, float r, const Ray& ray, const Hit& hit, Counts& n) {
  if (!hit.found()) return;
  ++n.hits;
  const Real t = hit.t;
  const Real px = ray.origin.x + t * ray.dir.x, py = ray.origin.y + t * ray.dir.y,
             pz = ray.origin.z + t * ray.dir.z;
  const Real ex = px - c.x, ey = py - c.y, ez = pz - c.z;
  const Real gx = Real(c.x) - ray.origin.x, gy = Real(c.y) - ray.origin.y,
             gz = Real(c.z) - ray.origin.z;
  const Real g = std::sqrt(gx * gx + gy * gy + gz * gz);
  const Real off = std::abs(std::sqrt(ex * ex + ey * ey + ez * ez) - Real(r));
  const Real scale = kU * (Real(r) + g);
  n.worst_point = std::max(n.worst_point, off / scale);
  n.off_sphere += off > kPointBound * scale;
  // No point of the sphere lies farther than |c - o| + r from the origin.
  const Real dir = std::sqrt(Real(ray.dir.x) * ray.dir.x + Real(ray.dir.y) * ray.dir.y +
                             Real(ray.dir.z) * ray.dir.z);
  n.beyond_chord += std::abs(t) * dir > g + Real(r) + kPointBound * scale;
}

// How a tracer starts its next ray at a surface point p with outward normal n.
enum class Start { at_point, relative_tmin, offset_1e7, offset_1e6 };

Ray grazing_ray(Vec3 p, Vec3 n, Vec3 dir, float scale, Start start) {
  switch (start) {
    case Start::at_point:
      return {p, dir};
    case Start::relative_tmin:
      return {p, dir, 1e-6f * scale / length(dir)};
    case Start::offset_1e7:
      return {p + (1e-7f * scale) * n, dir};
    case Start::offset_1e6:
      return {p + (1e-6f * scale) * n, dir};
  }
  return {p, dir};
}

// The two cases of the report, with every kernel in views of 1 and of 33 spheres (the other 32
// of radius 0, so that the SIMD path runs). Exactly, both roots are <= 0: a miss.
TEST(Grazing, TangentFromTheSurfaceMisses) {
  for (const float tilt : {-1e-9f, -1e-7f}) {
    for (const std::size_t count : {1u, 33u}) {
      SphereSoA spheres;
      spheres.add({0, 0, 0}, 0.1f);
      while (spheres.size() < count)
        spheres.add({0, 0, 0}, 0.0f);
      const Ray ray{{0, -0.1f, 0}, {1, tilt, 0}};
      ASSERT_FALSE(reference({0, 0, 0}, 0.1f, ray).hit);
      for (const EntryTable* k : test::runnable_kernels()) {
        const Hit hit = k->intersect(spheres.view(), ray);
        EXPECT_FALSE(hit.found()) << test::name_of(k) << " tilt " << tilt << " view of " << count
                                  << ": id " << hit.id << " t " << hit.t;
        EXPECT_FALSE(k->occluded(spheres.view(), ray)) << test::name_of(k);
      }
    }
  }
}

// Rays from points on spheres of radius 1e-3 to 1e4 whose centres lie up to 1e5 from the
// origin of coordinates, leaving tangentially or tilted outwards by 1e-7 to 1e-3, started at the
// point, with a tmin relative to its scale, or moved out along the normal.
TEST(Grazing, RaysFromSurfacePointsStayOnTheirSphere) {
  const std::size_t per_row = test::scaled(10000);
  const auto kernels = test::runnable_kernels();
  std::vector<Counts> counts(kernels.size());
  std::mt19937 rng(20261123);
  for (const float radius : {1e-3f, 1e-1f, 1.0f, 1e2f, 1e4f}) {
    for (const float distance : {0.0f, 1.0f, 1e2f, 1e5f}) {
      const Vec3 center = distance * test::unit_vector(rng);
      // One sphere in a view of 33 (radius-0 padding), and the same sphere among decoys, as
      // brute force and as a tree: the tree must return brute force's bits.
      SphereSoA alone, crowd;
      alone.add(center, radius);
      crowd.add(center, radius);
      for (int i = 0; i < 32; ++i)
        alone.add(center, 0.0f);
      for (int i = 0; i < 40; ++i)
        crowd.add(center + (radius * test::uniform(rng, 1.0f, 20.0f)) * test::unit_vector(rng),
                  radius * test::uniform(rng, 0.2f, 1.0f));
      std::vector<SphereBVH> trees;
      for (const EntryTable* k : kernels)
        trees.emplace_back(crowd.view(), k->isa);
      for (const float tilt : {0.0f, 1e-7f, 1e-5f, 1e-3f}) {
        for (const Start start :
             {Start::at_point, Start::relative_tmin, Start::offset_1e7, Start::offset_1e6}) {
          for (std::size_t i = 0; i < per_row; ++i) {
            const Vec3 n = test::unit_vector(rng);
            const Vec3 p = center + radius * n;
            const Vec3 tangent = normalize(cross(n, test::unit_vector(rng)));
            const float dir_length = std::exp(test::uniform(rng, std::log(0.1f), std::log(10.0f)));
            const Vec3 dir = normalize(tangent + tilt * n) * dir_length;
            const Ray ray = grazing_ray(p, n, dir, std::max(length(p), radius), start);
            const Exact exact = reference(center, radius, ray);
            std::array<Hit, 8> answers{};
            for (std::size_t k = 0; k < kernels.size(); ++k) {
              Counts& c = counts[k];
              ++c.rays;
              const Hit hit = kernels[k]->intersect(alone.view(), ray);
              answers[k] = hit;
              check_point(center, radius, ray, hit, c);
              if (exact.within_rounding)
                ++c.undecided;
              else
                c.wrong_decision += hit.found() != exact.hit;
              c.isa_mismatch += hit.t != answers[0].t || hit.id != answers[0].id;
              const Hit brute = kernels[k]->intersect(crowd.view(), ray);
              const Hit tree = intersect(trees[k], ray);
              c.bvh_mismatch += tree.t != brute.t || tree.id != brute.id;
              if (tree.found()) {
                const SphereView v = crowd.view();
                check_point({v.cx[tree.id], v.cy[tree.id], v.cz[tree.id]}, v.radius[tree.id], ray,
                            tree, c);
              }
            }
          }
        }
      }
    }
  }
  for (std::size_t k = 0; k < kernels.size(); ++k) {
    const Counts& c = counts[k];
    std::cout << test::name_of(kernels[k]) << ": " << c.rays << " rays, " << c.hits
              << " hits checked; off the sphere " << c.off_sphere << ", beyond the chord "
              << c.beyond_chord << ", decision unlike the reference " << c.wrong_decision
              << " (within rounding: " << c.undecided << "), unlike " << test::name_of(kernels[0])
              << " " << c.isa_mismatch << ", tree unlike brute force " << c.bvh_mismatch
              << "; worst point " << static_cast<double>(c.worst_point) << " u (r + |c - o|)\n";
    EXPECT_EQ(c.off_sphere, 0u) << test::name_of(kernels[k]);
    EXPECT_EQ(c.beyond_chord, 0u) << test::name_of(kernels[k]);
    EXPECT_EQ(c.wrong_decision, 0u) << test::name_of(kernels[k]);
    EXPECT_EQ(c.isa_mismatch, 0u) << test::name_of(kernels[k]);
    EXPECT_EQ(c.bvh_mismatch, 0u) << test::name_of(kernels[k]);
    EXPECT_GT(c.hits, c.rays / 10) << "the rays must hit often enough for the checks to bite";
  }
}

}  // namespace
}  // namespace sphray
