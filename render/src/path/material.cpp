#include "sphray/render/material.hpp"

#include <array>
#include <cmath>

namespace sphray::render {
namespace {

constexpr std::array<std::string_view, 3> kKindNames = {"lambertian", "metal", "dielectric"};

// The book's near_zero: a Lambertian direction n + u that almost cancels would make a
// degenerate ray.
bool near_zero(Vec3 v) {
  constexpr float s = 1e-8f;
  return std::fabs(v.x) < s && std::fabs(v.y) < s && std::fabs(v.z) < s;
}

Scattered lambertian(const Material& m, Vec3 normal, PathRandom& random) {
  Vec3 direction = normal + random.unit_vector();
  if (near_zero(direction)) direction = normal;
  return {m.albedo, direction};
}

std::optional<Scattered> metal(const Material& m, Vec3 incoming, Vec3 normal, PathRandom& random) {
  Vec3 direction = reflect(normalize(incoming), normal);
  if (m.fuzz > 0.0f) direction = normalize(direction) + m.fuzz * random.unit_vector();
  if (dot(direction, normal) <= 0.0f) return std::nullopt;  // fuzzed below the surface
  return Scattered{m.albedo, direction};
}

Scattered dielectric(const Material& m, Vec3 incoming, Vec3 normal, bool front_face,
                     PathRandom& random) {
  const float eta = front_face ? 1.0f / m.ior : m.ior;
  const Vec3 unit = normalize(incoming);
  const float cosine = std::min(dot(-unit, normal), 1.0f);
  const float sine = std::sqrt(std::max(0.0f, 1.0f - cosine * cosine));
  const bool cannot_refract = eta * sine > 1.0f;  // total internal reflection
  // A matched index is no interface at all: its Fresnel reflectance is 0, Schlick's
  // approximation's is (1 - cos)^5 (docs/decisions.md).
  const bool reflects = cannot_refract || (eta != 1.0f && schlick(cosine, eta) > random.uniform());
  return {{1.0f, 1.0f, 1.0f}, reflects ? reflect(unit, normal) : refract(unit, normal, eta)};
}

}  // namespace

std::string_view material_kind_name(MaterialKind kind) {
  return kKindNames[static_cast<std::size_t>(kind)];
}

std::optional<MaterialKind> parse_material_kind(std::string_view name) {
  for (std::size_t i = 0; i < kKindNames.size(); ++i) {
    if (kKindNames[i] == name) return static_cast<MaterialKind>(i);
  }
  return std::nullopt;
}

Vec3 PathRandom::unit_vector() {
  // Marsaglia (1972): (u, v) uniform in the unit disk by rejection (accepted with probability
  // pi/4), s = u^2 + v^2, then (2u sqrt(1 - s), 2v sqrt(1 - s), 1 - 2s) is uniform on the
  // sphere; one square root and no trigonometry, much cheaper than sampling with sincos
  // (docs/history.md, "Also tried, and the steps before the rounds").
  for (;;) {
    const float u = 2.0f * uniform() - 1.0f;
    const float v = 2.0f * uniform() - 1.0f;
    const float s = u * u + v * v;
    if (s >= 1.0f) continue;
    const float scale = 2.0f * std::sqrt(1.0f - s);
    return {u * scale, v * scale, 1.0f - 2.0f * s};
  }
}

Vec3 PathRandom::in_unit_disk() {
  for (;;) {
    const float x = 2.0f * uniform() - 1.0f;
    const float y = 2.0f * uniform() - 1.0f;
    if (x * x + y * y < 1.0f) return {x, y, 0.0f};
  }
}

Vec3 refract(Vec3 v, Vec3 n, float eta) {
  const float cosine = std::min(dot(-v, n), 1.0f);
  const Vec3 across = eta * (v + cosine * n);
  const Vec3 along = -std::sqrt(std::fabs(1.0f - length_squared(across))) * n;
  return across + along;
}

float schlick(float cosine, float eta) {
  float r0 = (1.0f - eta) / (1.0f + eta);
  r0 = r0 * r0;
  return r0 + (1.0f - r0) * std::pow(1.0f - cosine, 5.0f);
}

std::optional<Scattered> scatter(const Material& material, Vec3 incoming, const Surface& surface,
                                 PathRandom& random) {
  // The normal against the incoming ray, as the book's set_face_normal keeps it.
  const Vec3 normal = surface.front_face ? surface.normal : -surface.normal;
  switch (material.kind) {
    case MaterialKind::lambertian:
      return lambertian(material, normal, random);
    case MaterialKind::metal:
      return metal(material, incoming, normal, random);
    case MaterialKind::dielectric:
      return dielectric(material, incoming, normal, surface.front_face, random);
  }
  return std::nullopt;
}

}  // namespace sphray::render
