// The materials of Ray Tracing in One Weekend (Lambertian, metal with fuzz, dielectric with
// Schlick's reflectance), the sky that lights them, and the counter-based random numbers the
// path tracer draws from, so that every sample is a function of (seed, pixel, sample, bounce).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "sphray/sphray.hpp"

namespace sphray::render {

enum class MaterialKind { lambertian, metal, dielectric };

/// "lambertian", "metal", "dielectric": the names scene files use.
std::string_view material_kind_name(MaterialKind kind);
std::optional<MaterialKind> parse_material_kind(std::string_view name);

struct Material {
  MaterialKind kind = MaterialKind::lambertian;
  Vec3 albedo{0.5f, 0.5f, 0.5f};  // lambertian and metal; each component in [0, 1]
  float fuzz = 0.0f;              // metal: radius of the sphere the reflection is jittered in
  float ior = 1.5f;               // dielectric: index of refraction (> 0) against the outside
};

/// Light from every direction a path escapes in: the book's gradient, horizon (white) below to
/// zenith (sky blue) above by a = 0.5 (unit(dir).y + 1). Equal colours make a uniform sky.
struct Sky {
  Vec3 horizon{1.0f, 1.0f, 1.0f};
  Vec3 zenith{0.5f, 0.7f, 1.0f};

  Vec3 radiance(Vec3 dir) const {
    const float a = 0.5f * (dir.y / length(dir) + 1.0f);  // normalize(dir).y, bit for bit
    return (1.0f - a) * horizon + a * zenith;
  }
};

/// One path's uniform floats, from a key of (seed, pixel, sample): SplitMix64 (Steele, Lea and
/// Flood, 2014) over a counter started at a hash of the key. The path draws from it in order,
/// bounce after bounce, so no draw depends on which thread or in which order other samples
/// were traced, and the key is hashed once per path rather than once per bounce.
class PathRandom {
 public:
  PathRandom() = default;
  PathRandom(std::uint64_t seed, std::uint64_t pixel, std::uint32_t sample)
      : state_(mix(mix(seed_hash(seed) ^ pixel) ^ (std::uint64_t{sample} << 32))) {}
  /// The part of the key's hash that depends on the seed alone.
  static std::uint64_t seed_hash(std::uint64_t seed) { return mix(seed + 0x632be59bd9b4e019ull); }
  /// Uniform in [0, 1), 24 bits, exact in float.
  float uniform() {
    state_ += kStep;
    return at(state_);
  }
  /// The counter behind the draws: the k-th draw from here (k = 1, 2, ...) is
  /// at(counter() + k * kStep). The path tracer's wavefront keeps each path's counter in an array
  /// of integers and draws from it, the same draws in the same order.
  static constexpr std::uint64_t kStep = 0x9e3779b97f4a7c15ull;
  std::uint64_t counter() const { return state_; }
  static float at(std::uint64_t counter) {
    return static_cast<float>(mix(counter) >> 40) * 0x1p-24f;
  }
  /// Uniform on the unit sphere.
  Vec3 unit_vector();
  /// Uniform in the unit disk: {x, y, 0}.
  Vec3 in_unit_disk();

  /// SplitMix64's finaliser.
  static std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t state_ = 0;
};

/// Where a path goes on from a surface, and what the surface lets through.
struct Scattered {
  Vec3 attenuation;
  Vec3 direction;  // not normalised (a Lambertian direction is n + a unit vector, as in the book)
};

/// The book's scatter functions (Ray Tracing in One Weekend, v4, chapters 10 to 11): nothing
/// for an absorbed path (a fuzzed metal reflection below the surface). surface is where
/// incoming (the ray's direction) met the sphere.
std::optional<Scattered> scatter(const Material& material, Vec3 incoming, const Surface& surface,
                                 PathRandom& random);

/// Mirror direction of unit vector v about unit normal n.
inline Vec3 reflect(Vec3 v, Vec3 n) {
  return v - 2.0f * dot(v, n) * n;
}

/// Snell's law for unit v arriving against unit n, eta = n_incident / n_transmitted, where
/// eta * sin(theta_i) <= 1 (the book's form: the part across n and the part along it).
Vec3 refract(Vec3 v, Vec3 n, float eta);

/// Schlick's approximation of the Fresnel reflectance at cosine cosine for relative index eta.
float schlick(float cosine, float eta);

}  // namespace sphray::render
