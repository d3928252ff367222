// The radii the contract accepts (docs/kernel.md, "Contract"): those whose square is a normal,
// finite number of the query's scalar type, as for a ray's direction length. Plain constants,
// shared by the SIMD kernels (brute/sphere_lanes.hpp, point/point_lanes.hpp) and the scalar code
// (brute/validity.hpp).
#pragma once

namespace sphray::detail {

template <class S>
struct RadiusRange;

// The smallest valid radius: 2^-63 squared is 2^-126 = FLT_MIN, the smallest normal float, and
// every float below 2^-63 squares into the denormals (or to 0). There the discriminant
// r^2 - |v|^2 loses its relative precision: both terms can underflow to 0, and a ray 8e6 radii
// away then "grazes" the sphere at disc = 0 (issue 30).
// The first invalid radius: 2^64 squared overflows to infinity. The ray kernels need no test
// for it (r^2 = inf makes the roots +-inf or NaN, never inside an open interval (tmin, tmax));
// the tree's builder and the point queries, which never square r, test it.
template <>
struct RadiusRange<float> {
  static constexpr float kMin = 0x1p-63f;
  static constexpr float kLimit = 0x1p64f;
};
// The same bounds for double: 2^-511 squared is DBL_MIN, 2^512 squared overflows.
template <>
struct RadiusRange<double> {
  static constexpr double kMin = 0x1p-511;
  static constexpr double kLimit = 0x1p512;
};

constexpr float kMinRadius = RadiusRange<float>::kMin;
constexpr float kRadiusLimit = RadiusRange<float>::kLimit;

}  // namespace sphray::detail
