// Vec3: three floats with the arithmetic a ray tracer needs.
#pragma once

// Every public C++ header includes this one, so the check of the language standard lives here:
// without it, a C++17 build fails later on std::span with no word of why. (C programs use
// <sphray/sphray.h>, which needs no C++ at all.)
#if !defined(__cplusplus) || __cplusplus < 202002L
#error "sphray's C++ headers need C++20: compile with -std=c++20 (C: <sphray/sphray.h>)"
#endif

#include <cmath>

namespace sphray {

struct Vec3 {
  float x, y, z;

  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3& operator+=(Vec3 v) { return *this = {x + v.x, y + v.y, z + v.z}; }
  constexpr Vec3& operator-=(Vec3 v) { return *this = {x - v.x, y - v.y, z - v.z}; }
  constexpr Vec3& operator*=(float s) { return *this = {x * s, y * s, z * s}; }
  constexpr Vec3& operator/=(float s) { return *this = {x / s, y / s, z / s}; }
  constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  friend constexpr bool operator==(Vec3, Vec3) = default;
};

constexpr Vec3 operator+(Vec3 a, Vec3 b) {
  return a += b;
}
constexpr Vec3 operator-(Vec3 a, Vec3 b) {
  return a -= b;
}
constexpr Vec3 operator*(Vec3 a, float s) {
  return a *= s;
}
constexpr Vec3 operator*(float s, Vec3 a) {
  return a *= s;
}
constexpr Vec3 operator/(Vec3 a, float s) {
  return a /= s;
}
/// Component-wise product (colours, scaling).
constexpr Vec3 operator*(Vec3 a, Vec3 b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}

constexpr float dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr float length_squared(Vec3 v) {
  return dot(v, v);
}
inline float length(Vec3 v) {
  return std::sqrt(dot(v, v));
}
/// Unit vector along v. The zero vector has no direction: the result is NaN.
inline Vec3 normalize(Vec3 v) {
  return v / length(v);
}
inline bool isfinite(Vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace sphray
