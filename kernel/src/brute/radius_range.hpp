// The radii the contract accepts (docs/kernel.md, "Contract"): those whose square is a normal,
// finite float, as for a ray's direction length. Plain constants, shared by the SIMD kernels
// (brute/sphere_lanes.hpp, point/point_lanes.hpp) and the scalar code (brute/validity.hpp).
#pragma once

namespace sphray::detail {

// The smallest valid radius: 2^-63 squared is 2^-126 = FLT_MIN, the smallest normal float, and
// every float below 2^-63 squares into the denormals (or to 0). There the discriminant
// r^2 - |v|^2 loses its relative precision: both terms can underflow to 0, and a ray 8e6 radii
// away then "grazes" the sphere at disc = 0 (issue 30).
constexpr float kMinRadius = 0x1p-63f;

// The first invalid radius: 2^64 squared overflows to infinity. The ray kernels need no test
// for it (r^2 = inf makes the roots +-inf or NaN, never inside an open interval (tmin, tmax));
// the tree's builder and the point queries, which never square r, test it.
constexpr float kRadiusLimit = 0x1p64f;

}  // namespace sphray::detail
