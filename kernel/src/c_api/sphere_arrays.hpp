// The sphere arrays a C caller passes (four pointers, a count and a stride), in float or in
// double, checked and copied into a SphereSoA or SphereSoAd.
#pragma once

#include <cstddef>

#include "sphray/sphray.hpp"

namespace sphray::c_api {

template <Scalar S>
struct SphereArrays {
  const S* cx;
  const S* cy;
  const S* cz;
  const S* r;
  std::size_t count;
  std::size_t stride_bytes;  // 0: packed values
};

/// SPHRAY_OK, or the status of the first problem (NULL pointer, count 0 or over 2^32 - 1,
/// stride not 0 and not a positive multiple of sizeof(S), a pointer not aligned for S), with
/// the message set.
template <Scalar S>
int check(const SphereArrays<S>& arrays, const char* function) noexcept;

/// The spheres, copied. Call after check().
template <Scalar S>
BasicSphereSoA<S> copy(const SphereArrays<S>& arrays);

/// The spheres written over those of spheres (the same count, checked by the caller), in
/// place: spheres keeps its arrays, so a query that reads them meanwhile (a documented race,
/// sphray.h) sees each value old or new, never freed memory. Allocates nothing and cannot
/// fail. Masks are kept.
template <Scalar S>
void overwrite(const SphereArrays<S>& arrays, BasicSphereSoA<S>& spheres);

}  // namespace sphray::c_api
