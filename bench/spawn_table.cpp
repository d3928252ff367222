// The spawn table: how often a ray spawned from a hit (sphray::spawn) goes wrong, in float and
// in double, for spheres of radius 1e-3 to 1e4 at 1 to 1e5 from the origin of coordinates, on
// every instruction set this machine runs. A hit comes from a ray from outside the sphere; from
// its surface() one ray leaves outward (it must never meet the sphere again) and one inward (it
// must meet the far side). Then the smallest radius/distance ratio at which each precision still
// holds (no failure either way), at distances 1 and 1e5. Prints markdown (docs/double.md).
//
//   sphray_spawn_table [--rays N]   (N rays per row and instruction set; 200000 by default)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <sphray/sphray.hpp>

#include "dispatch/entry_table.hpp"

namespace {

using sphray::Isa;
using sphray::detail::EntryTable;

// The sphere in lane 0 of a view of 16 (the others never hit), so that every instruction set's
// batches run rather than the scalar loop the query plan takes for one sphere.
template <class S>
struct OneSphere {
  static constexpr std::size_t kCount = 16;
  S cx[kCount] = {}, cy[kCount] = {}, cz[kCount] = {}, r[kCount] = {};
  sphray::BasicSphereView<S> view() const { return {cx, cy, cz, r, kCount}; }
};

template <class S>
sphray::BasicHit<S> intersect(const EntryTable& k, const sphray::BasicSphereView<S>& v,
                              const sphray::BasicRay<S>& ray) {
  if constexpr (std::is_same_v<S, float>)
    return k.intersect(v, ray);
  else
    return k.intersect_d(v, ray);
}

sphray::Vec3d unit_vector(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double z = u(rng), phi = 3.141592653589793 * u(rng);
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

template <class S>
sphray::BasicVec3<S> to(sphray::Vec3d v) {
  return {static_cast<S>(v.x), static_cast<S>(v.y), static_cast<S>(v.z)};
}

struct Rates {
  std::size_t cases = 0, no_hit = 0, out_failed = 0, in_failed = 0;
  double out_rate() const { return cases == 0 ? 0.0 : 100.0 * out_failed / cases; }
  double in_rate() const { return cases == 0 ? 0.0 : 100.0 * in_failed / cases; }
  bool holds() const { return cases > 0 && out_failed == 0 && in_failed == 0; }
};

// n cases on a sphere of radius r whose centre lies at distance d from the origin, in S.
template <class S>
Rates measure(const EntryTable& k, double radius, double distance, std::size_t n,
              std::uint64_t seed) {
  using V = sphray::BasicVec3<S>;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  OneSphere<S> sphere;
  Rates rates;
  for (std::size_t i = 0; i < n; ++i) {
    const V centre = to<S>(distance * unit_vector(rng));
    sphere.cx[0] = centre.x, sphere.cy[0] = centre.y, sphere.cz[0] = centre.z;
    sphere.r[0] = static_cast<S>(radius);
    const auto view = sphere.view();
    // From 1.01 to 1000 radii away, at a point of the visible side.
    const double away = radius * std::exp(std::log(1.01) + u(rng) * std::log(1e3 / 1.01));
    const V origin = centre + to<S>(away * unit_vector(rng));
    const V target = centre + to<S>(0.9 * radius * unit_vector(rng));
    const sphray::BasicRay<S> ray{origin, target - origin};
    const auto hit = intersect(k, view, ray);
    if (!hit.found()) {
      ++rates.no_hit;
      continue;
    }
    ++rates.cases;
    const auto surface = sphray::surface(view, ray, hit);
    // A direction in the outer hemisphere, grazing ones included, and its mirror inward.
    V out = to<S>(unit_vector(rng));
    if (sphray::dot(out, surface.normal) < S(0)) out = -out;
    if (intersect(k, view, sphray::spawn(surface, out)).found()) ++rates.out_failed;
    if (!intersect(k, view, sphray::spawn(surface, -out)).found()) ++rates.in_failed;
  }
  return rates;
}

const char* name_of(double x) {
  static char text[8][16];
  static int next = 0;
  char* t = text[next++ % 8];
  std::snprintf(t, 16, "%g", x);
  return t;
}

template <class S>
void table(const std::vector<const EntryTable*>& kernels, std::size_t rays, const char* precision) {
  const double radii[] = {1e-3, 1e-1, 1e1, 1e3, 1e4};
  const double distances[] = {1, 1e2, 1e4, 1e5};
  std::printf("\n%s, %zu rays per row and instruction set (the worst instruction set's rate):\n\n",
              precision, rays);
  std::printf(
      "| radius | distance | outward meet it again | inward miss its far side |"
      " primary rays that missed |\n|---:|---:|---:|---:|---:|\n");
  std::uint64_t seed = 1;
  for (const double r : radii) {
    for (const double d : distances) {
      Rates worst;
      for (const EntryTable* k : kernels) {
        const Rates rates = measure<S>(*k, r, d, rays, seed);
        if (k == kernels.front() ||
            rates.out_rate() + rates.in_rate() > worst.out_rate() + worst.in_rate())
          worst = rates;
      }
      ++seed;
      std::printf("| %s | %s | %.2f%% | %.2f%% | %zu |\n", name_of(r), name_of(d), worst.out_rate(),
                  worst.in_rate(), worst.no_hit);
    }
  }
}

// The smallest ratio 10^-k (k = 0 to 16) at which every instruction set holds at distance d,
// after which a step down fails (or none does).
template <class S>
std::string smallest_ratio(const std::vector<const EntryTable*>& kernels, double d,
                           std::size_t rays) {
  double holding = 0;
  for (int k = 0; k <= 16; ++k) {
    const double ratio = std::pow(10.0, -k);
    bool holds = true;
    for (const EntryTable* kernel : kernels)
      holds = holds && measure<S>(*kernel, ratio * d, d, rays, 1000 + k).holds();
    if (!holds) break;
    holding = ratio;
  }
  return holding == 0 ? std::string("none") : name_of(holding);
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t rays = 200000;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--rays") == 0 && i + 1 < argc) {
      rays = std::strtoull(argv[++i], nullptr, 10);
    } else {
      std::fprintf(stderr, "usage: %s [--rays N]\n", argv[0]);
      return 2;
    }
  }
  std::vector<const EntryTable*> kernels;
  std::string names;
  for (const Isa isa : sphray::supported_isas()) {
    kernels.push_back(sphray::detail::find_entries(isa));
    names += std::string(names.empty() ? "" : ", ") + std::string(sphray::isa_name(isa));
  }
  std::printf("sphray %s, instruction sets: %s\n", std::string(sphray::kVersion).c_str(),
              names.c_str());
  table<float>(kernels, rays, "float");
  table<double>(kernels, rays, "double");
  const std::size_t sweep = std::max<std::size_t>(rays / 10, 1);
  std::printf(
      "\nThe smallest radius/distance ratio 10^-k at which no ray fails either way (%zu "
      "rays per ratio and instruction set):\n\n| precision | distance 1 | distance 1e5 |\n"
      "|---|---:|---:|\n",
      sweep);
  std::printf("| float | %s | %s |\n", smallest_ratio<float>(kernels, 1, sweep).c_str(),
              smallest_ratio<float>(kernels, 1e5, sweep).c_str());
  std::printf("| double | %s | %s |\n", smallest_ratio<double>(kernels, 1, sweep).c_str(),
              smallest_ratio<double>(kernels, 1e5, sweep).c_str());
  return 0;
}
