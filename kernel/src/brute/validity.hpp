// The contract's tests for rays and spheres that miss everything, shared by the scalar code
// paths and the BVH builder. The SIMD kernel has its own copy in SphereLanes::setup: these call
// the public headers' inline functions, which per-ISA units must not (simd/isa_namespace.hpp).
#pragma once

#include <cmath>

#include "brute/radius_range.hpp"
#include "sphray/ray.hpp"
#include "sphray/vec3.hpp"

namespace sphray::detail {

/// False for a NaN or infinite origin or direction component, a direction whose squared length
/// is not a normal finite number, a NaN bound, or !(tmin < tmax).
bool valid_ray(const Ray& ray);
bool valid_ray(const Rayd& ray);

/// False for a NaN or infinite centre component, or a radius whose square is not a normal,
/// finite number (radius_range.hpp: NaN, <= 0, below 2^-63 or from 2^64 on in float): such a
/// sphere is never hit, and never found by the point queries.
template <Scalar S>
bool valid_sphere(BasicVec3<S> center, S radius) {
  return isfinite(center) && radius >= RadiusRange<S>::kMin && radius < RadiusRange<S>::kLimit;
}

}  // namespace sphray::detail
