// The sphere arrays a C caller passes (four pointers, a count and a stride), checked and
// copied into a SphereSoA.
#pragma once

#include <cstddef>

#include "sphray/sphray.hpp"

namespace sphray::c_api {

struct SphereArrays {
  const float* cx;
  const float* cy;
  const float* cz;
  const float* r;
  std::size_t count;
  std::size_t stride_bytes;  // 0: packed floats
};

/// SPHRAY_OK, or the status of the first problem (NULL pointer, count 0 or over 2^32 - 1,
/// stride not 0 and not a positive multiple of 4, a pointer not aligned for float), with the
/// message set.
int check(const SphereArrays& arrays, const char* function) noexcept;

/// The spheres, copied. Call after check().
SphereSoA copy(const SphereArrays& arrays);

/// The spheres written over those of spheres (the same count, checked by the caller), in
/// place: spheres keeps its arrays, so a query that reads them meanwhile (a documented race,
/// sphray.h) sees each value old or new, never freed memory. Allocates nothing and cannot
/// fail. Masks are kept.
void overwrite(const SphereArrays& arrays, SphereSoA& spheres);

}  // namespace sphray::c_api
