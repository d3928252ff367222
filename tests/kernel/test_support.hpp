// Helpers shared by the kernel tests: random scenes and rays, and a way to run a check on every
// kernel this machine can run (each instruction set on its own, plus the dispatched queries).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include <sphray/sphray.hpp>

// The library's insides (the sphray_kernel_internals target): each instruction set's entry
// points, and a tree's arrays.
#include "bvh/bvh_data.hpp"
#include "dispatch/entry_table.hpp"

namespace sphray {
using detail::active_entries;
using detail::entries_for_size;
using detail::EntryTable;
using detail::find_entries;
}  // namespace sphray

namespace sphray {
// Names instruction sets in gtest's output ("GetParam() = avx2").
inline void PrintTo(Isa isa, std::ostream* os) {
  *os << isa_name(isa);
}
}  // namespace sphray

namespace sphray::test {

// Sphere arrays that the test owns, with a configurable misalignment, so views with any start
// address and any count can be made (the kernel must not assume SphereSoA's padding).
struct LooseSpheres {
  std::vector<float> storage[4];
  std::size_t offset = 0;  // floats skipped at the front of each array
  std::size_t count = 0;

  explicit LooseSpheres(std::size_t misalign = 1) : offset(misalign) {
    for (auto& s : storage)
      s.assign(offset, 0.0f);
  }
  void add(Vec3 c, float r) {
    storage[0].push_back(c.x);
    storage[1].push_back(c.y);
    storage[2].push_back(c.z);
    storage[3].push_back(r);
    ++count;
  }
  SphereView view() const {
    return {storage[0].data() + offset, storage[1].data() + offset, storage[2].data() + offset,
            storage[3].data() + offset, count};
  }
};

// Sanitizer builds run ten to fifty times slower: their test presets set SPHRAY_TEST_SCALE
// (0 < scale <= 1) to trace that fraction of the random rays. Every case still runs; the
// release run traces the full counts.
inline double ray_scale() {
  static const double scale = [] {
    const char* text = std::getenv("SPHRAY_TEST_SCALE");
    const double s = text != nullptr ? std::atof(text) : 1.0;
    return s > 0.0 && s <= 1.0 ? s : 1.0;
  }();
  return scale;
}

inline std::size_t scaled(std::size_t rays) {
  return std::max<std::size_t>(1,
                               static_cast<std::size_t>(static_cast<double>(rays) * ray_scale()));
}

inline float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

inline Vec3 random_in_box(std::mt19937& rng, float half) {
  return {uniform(rng, -half, half), uniform(rng, -half, half), uniform(rng, -half, half)};
}

// A direction of random length in [0.1, 10] (the contract allows any non-zero length).
inline Vec3 random_direction(std::mt19937& rng) {
  Vec3 d;
  do {
    d = random_in_box(rng, 1.0f);
  } while (length_squared(d) < 1e-4f || length_squared(d) > 1.0f);
  return normalize(d) * std::exp(uniform(rng, std::log(0.1f), std::log(10.0f)));
}

// A direction uniform on the unit sphere.
inline Vec3 unit_vector(std::mt19937& rng) {
  Vec3 v;
  do {
    v = random_in_box(rng, 1.0f);
  } while (length_squared(v) < 1e-3f || length_squared(v) > 1.0f);
  return normalize(v);
}

// n spheres in a box of half-size 10 whose radii make about half the rays hit something.
template <class Store>
void fill_random(Store& store, std::size_t n, std::mt19937& rng) {
  const float r_mean = n == 0 ? 1.0f : 6.0f / std::cbrt(static_cast<float>(n) + 1.0f);
  for (std::size_t i = 0; i < n; ++i)
    store.add(random_in_box(rng, 10.0f), r_mean * uniform(rng, 0.3f, 1.7f));
}

inline std::vector<Ray> random_rays(std::size_t n, std::mt19937& rng) {
  std::vector<Ray> rays(n);
  for (auto& r : rays)
    r = Ray{random_in_box(rng, 12.0f), random_direction(rng)};
  return rays;
}

// Scenes of the shapes that stress the queries beyond the closest hit: random; clustered (every
// sphere overlapping many); nested (concentric shells); identical (one sphere many times); radii
// from 1e-3 to 10; and poisoned (every third sphere invalid: radius 0 or negative, a NaN or
// infinite field).
enum class Shape { random, clustered, nested, identical, mixed_radii, poisoned };

inline SphereSoA make_scene(Shape shape, std::size_t n, std::mt19937& rng) {
  SphereSoA s;
  for (std::size_t i = 0; i < n; ++i) {
    switch (shape) {
      case Shape::random:
        s.add(test::random_in_box(rng, 10.0f), test::uniform(rng, 0.2f, 1.5f));
        break;
      case Shape::clustered:
        s.add(test::random_in_box(rng, 1.0f), test::uniform(rng, 0.5f, 2.0f));
        break;
      case Shape::nested:
        s.add({1, 2, 3}, 0.5f + 0.25f * static_cast<float>(i));
        break;
      case Shape::identical:
        s.add({-1, 0.5f, 2}, 3.0f);
        break;
      case Shape::mixed_radii:
        s.add(test::random_in_box(rng, 10.0f), std::pow(10.0f, test::uniform(rng, -3.0f, 1.0f)));
        break;
      case Shape::poisoned: {
        Vec3 c = test::random_in_box(rng, 10.0f);
        float r = test::uniform(rng, 0.2f, 1.5f);
        const float bad[] = {0.0f, -1.0f, NAN, INFINITY};
        if (i % 3 == 0) (i % 2 == 0 ? r : c.y) = bad[(i / 3) % 4];
        s.add(c, r);
        break;
      }
    }
  }
  return s;
}

// Every kernel this machine runs, by instruction set (scalar included).
inline std::vector<const EntryTable*> runnable_kernels() {
  std::vector<const EntryTable*> kernels;
  for (Isa isa : supported_isas())
    kernels.push_back(find_entries(isa));
  return kernels;
}

inline std::string name_of(const EntryTable* k) {
  return std::string(isa_name(k->isa));
}

// Every shape at sizes from 0 to 3,000 spheres, each with a tree per kernel of kernels:
// visit(view, trees, sphere count).
template <class Visit>
void for_each_query_scene(std::mt19937& rng, const std::vector<const EntryTable*>& kernels,
                          Visit&& visit) {
  const Shape shapes[] = {Shape::random,    Shape::clustered,   Shape::nested,
                          Shape::identical, Shape::mixed_radii, Shape::poisoned};
  const std::size_t sizes[] = {0, 1, 3, 17, 40, 300, 3000};
  for (const Shape shape : shapes) {
    for (const std::size_t n : sizes) {
      const SphereSoA scene = make_scene(shape, n, rng);
      std::vector<SphereBVH> trees;
      for (const EntryTable* k : kernels)
        trees.emplace_back(scene.view(), k->isa);
      visit(scene.view(), trees, n);
    }
  }
}

}  // namespace sphray::test
