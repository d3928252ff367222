#include "c_api/sphere_arrays.hpp"

#include <cstdint>
#include <cstring>

#include "c_api/checks.hpp"

namespace sphray::c_api {
namespace {

// Ids are uint32_t and SPHRAY_NO_HIT is one of them: SphereSoA's own limit.
constexpr std::size_t kMaxSpheres = 0xffffffffu;

bool float_aligned(const float* p) {
  return reinterpret_cast<std::uintptr_t>(p) % alignof(float) == 0;
}

float read(const float* base, std::size_t i, std::size_t stride) {
  float value;
  std::memcpy(&value, reinterpret_cast<const unsigned char*>(base) + i * stride, sizeof value);
  return value;
}

}  // namespace

int check(const SphereArrays& a, const char* function) noexcept {
  if (a.count == 0) return SPHRAY_OK;  // no spheres: nothing is read, the arrays may be NULL
  if (a.cx == nullptr || a.cy == nullptr || a.cz == nullptr || a.r == nullptr)
    return fail(SPHRAY_ERROR_NULL_POINTER, function, "a sphere array (cx, cy, cz or r) is NULL");
  if (a.count > kMaxSpheres)
    return fail(SPHRAY_ERROR_TOO_LARGE, function, "count exceeds 2^32 - 1 spheres");
  if (a.stride_bytes % sizeof(float) != 0)
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function,
                "stride_bytes is not 0 nor a multiple of sizeof(float)");
  if (a.stride_bytes != 0 && (a.count - 1) > PTRDIFF_MAX / a.stride_bytes)
    return fail(SPHRAY_ERROR_TOO_LARGE, function, "count * stride_bytes exceeds PTRDIFF_MAX");
  if (!float_aligned(a.cx) || !float_aligned(a.cy) || !float_aligned(a.cz) || !float_aligned(a.r))
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function, "a sphere array is not aligned for float");
  return SPHRAY_OK;
}

SphereSoA copy(const SphereArrays& a) {
  const std::size_t stride = a.stride_bytes == 0 ? sizeof(float) : a.stride_bytes;
  SphereSoA spheres;
  spheres.reserve(a.count);
  for (std::size_t i = 0; i < a.count; ++i) {
    spheres.add({read(a.cx, i, stride), read(a.cy, i, stride), read(a.cz, i, stride)},
                read(a.r, i, stride));
  }
  return spheres;
}

void overwrite(const SphereArrays& a, SphereSoA& spheres) {
  const std::size_t stride = a.stride_bytes == 0 ? sizeof(float) : a.stride_bytes;
  for (std::size_t i = 0; i < a.count; ++i) {
    spheres.set(static_cast<std::uint32_t>(i),
                {read(a.cx, i, stride), read(a.cy, i, stride), read(a.cz, i, stride)},
                read(a.r, i, stride));
  }
}

}  // namespace sphray::c_api
