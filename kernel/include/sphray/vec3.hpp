// Vec3: three coordinates with the arithmetic a ray tracer needs, in float (Vec3) or double
// (Vec3d). Every public type of the queries is a template on its scalar, spelled for float
// without a suffix and for double with a "d" (docs/double.md).
#pragma once

// Every public C++ header includes this one, so the check of the language standard lives here:
// without it, a C++17 build fails later on std::span with no word of why. (C programs use
// <sphray/sphray.h>, which needs no C++ at all.)
#if !defined(__cplusplus) || __cplusplus < 202002L
#error "sphray's C++ headers need C++20: compile with -std=c++20 (C: <sphray/sphray.h>)"
#endif

#include <cmath>
#include <concepts>

namespace sphray {

/// The scalar types the kernel is written for.
template <class S>
concept Scalar = std::same_as<S, float> || std::same_as<S, double>;

template <Scalar S>
struct BasicVec3 {
  S x, y, z;

  constexpr BasicVec3 operator-() const { return {-x, -y, -z}; }
  constexpr BasicVec3& operator+=(BasicVec3 v) { return *this = {x + v.x, y + v.y, z + v.z}; }
  constexpr BasicVec3& operator-=(BasicVec3 v) { return *this = {x - v.x, y - v.y, z - v.z}; }
  constexpr BasicVec3& operator*=(S s) { return *this = {x * s, y * s, z * s}; }
  constexpr BasicVec3& operator/=(S s) { return *this = {x / s, y / s, z / s}; }
  constexpr S operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  friend constexpr bool operator==(BasicVec3, BasicVec3) = default;

  // The arithmetic as hidden friends: found for any BasicVec3 operand, and a scalar of another
  // type (2 * v, 0.5 * v) converts as it did before the type was a template.
  friend constexpr BasicVec3 operator+(BasicVec3 a, BasicVec3 b) { return a += b; }
  friend constexpr BasicVec3 operator-(BasicVec3 a, BasicVec3 b) { return a -= b; }
  friend constexpr BasicVec3 operator*(BasicVec3 a, S s) { return a *= s; }
  friend constexpr BasicVec3 operator*(S s, BasicVec3 a) { return a *= s; }
  friend constexpr BasicVec3 operator/(BasicVec3 a, S s) { return a /= s; }
  /// Component-wise product (colours, scaling).
  friend constexpr BasicVec3 operator*(BasicVec3 a, BasicVec3 b) {
    return {a.x * b.x, a.y * b.y, a.z * b.z};
  }
};

using Vec3 = BasicVec3<float>;
using Vec3d = BasicVec3<double>;

template <Scalar S>
constexpr S dot(BasicVec3<S> a, BasicVec3<S> b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <Scalar S>
constexpr BasicVec3<S> cross(BasicVec3<S> a, BasicVec3<S> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <Scalar S>
constexpr S length_squared(BasicVec3<S> v) {
  return dot(v, v);
}
template <Scalar S>
S length(BasicVec3<S> v) {
  return std::sqrt(dot(v, v));
}
/// Unit vector along v. The zero vector has no direction: the result is NaN.
template <Scalar S>
BasicVec3<S> normalize(BasicVec3<S> v) {
  return v / length(v);
}
template <Scalar S>
bool isfinite(BasicVec3<S> v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
/// v in another scalar type: exact from float to double, rounded to nearest the other way.
template <Scalar To, Scalar From>
constexpr BasicVec3<To> vec3_cast(BasicVec3<From> v) {
  return {static_cast<To>(v.x), static_cast<To>(v.y), static_cast<To>(v.z)};
}

}  // namespace sphray
