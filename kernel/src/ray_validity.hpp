// The contract's test for rays that miss everything, shared by the scalar code paths (the SIMD
// kernel has its own copy in SphereBatchKernel::setup: per-ISA units call no shared inline code).
#pragma once

#include "sphray/ray.hpp"

namespace sphray::detail {

/// False for a NaN or infinite origin or direction component, a direction whose squared length
/// is not a normal finite float, a NaN bound, or !(tmin < tmax).
bool valid_ray(const Ray& ray);

}  // namespace sphray::detail
