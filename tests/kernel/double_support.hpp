// Helpers shared by the double-precision tests: double sphere arrays with a misaligned start,
// random scenes and rays, bit-exact comparison, and a long-double reference for one sphere.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <sphray/sphray.hpp>

namespace sphray::test::doubles {

using Real = long double;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Spheres in double arrays with a misaligned start, and an optional mask per sphere.
struct DoubleSpheres {
  std::vector<double> storage[4];
  std::vector<std::uint32_t> masks;
  static constexpr std::size_t kOffset = 1;  // doubles skipped at the front of each array

  DoubleSpheres() {
    for (auto& s : storage)
      s.assign(kOffset, 0.0);
    masks.assign(kOffset, 0u);
  }
  void add(Vec3d c, double r, std::uint32_t mask = kAllBits) {
    storage[0].push_back(c.x), storage[1].push_back(c.y), storage[2].push_back(c.z);
    storage[3].push_back(r);
    masks.push_back(mask);
  }
  std::size_t size() const { return storage[0].size() - kOffset; }
  SphereViewd view(bool with_masks = false) const {
    return {storage[0].data() + kOffset,
            storage[1].data() + kOffset,
            storage[2].data() + kOffset,
            storage[3].data() + kOffset,
            size(),
            0,
            with_masks ? masks.data() + kOffset : nullptr};
  }
};

inline double uniform(std::mt19937& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
inline Vec3d in_box(std::mt19937& rng, double half) {
  return {uniform(rng, -half, half), uniform(rng, -half, half), uniform(rng, -half, half)};
}

// n spheres around `at`, in a box of half-size 10 scale, some overlapping, some nested.
inline DoubleSpheres random_spheres(std::mt19937& rng, std::size_t n, Vec3d at, double scale) {
  DoubleSpheres s;
  for (std::size_t i = 0; i < n; ++i)
    s.add(at + scale * in_box(rng, 10.0), scale * uniform(rng, 0.2, 2.5),
          static_cast<std::uint32_t>(rng()) | 1u << (i % 3));
  return s;
}

inline Rayd random_ray(std::mt19937& rng, Vec3d at, double scale) {
  Vec3d d;
  do {
    d = in_box(rng, 1.0);
  } while (length_squared(d) < 1e-4);
  return Rayd{at + scale * in_box(rng, 12.0), d * std::exp(uniform(rng, -2.0, 2.0))};
}

inline bool same_bits(const Hitd& a, const Hitd& b) {
  return std::bit_cast<std::uint64_t>(a.t) == std::bit_cast<std::uint64_t>(b.t) && a.id == b.id;
}

inline std::string describe(const Hitd& h) {
  char text[64];
  std::snprintf(text, sizeof text, "{t %a, id %u}", h.t, h.id);
  return text;
}

// The closest crossing of one sphere after tmin in long double on the double inputs (the
// textbook roots: long double's 11 more bits keep them well below double's rounding for these
// well-conditioned cases), and the discriminant relative to b^2, to know the grazing rays.
struct Exact {
  std::optional<Real> t;
  Real relative_disc = 0;
};
inline Exact exact_hit(const Rayd& ray, Vec3d c, double r) {
  const Real g[3] = {Real(c.x) - ray.origin.x, Real(c.y) - ray.origin.y, Real(c.z) - ray.origin.z};
  const Real d[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
  Real a = 0, b = 0, gg = 0;
  for (int i = 0; i < 3; ++i)
    a += d[i] * d[i], b += g[i] * d[i], gg += g[i] * g[i];
  const Real disc = b * b - a * (gg - Real(r) * r);
  Exact e;
  e.relative_disc = disc / (b * b + a * Real(r) * r);
  if (disc < 0) return e;
  const Real near = (b - std::sqrt(disc)) / a, far = (b + std::sqrt(disc)) / a;
  if (near > ray.tmin && near < ray.tmax)
    e.t = near;
  else if (far > ray.tmin && far < ray.tmax)
    e.t = far;
  return e;
}

}  // namespace sphray::test::doubles
