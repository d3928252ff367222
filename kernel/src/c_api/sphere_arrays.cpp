#include "c_api/sphere_arrays.hpp"

#include <cstdint>
#include <cstring>
#include <type_traits>

#include "c_api/checks.hpp"

namespace sphray::c_api {
namespace {

// Ids are uint32_t and SPHRAY_NO_HIT is one of them: SphereSoA's own limit.
constexpr std::size_t kMaxSpheres = 0xffffffffu;

template <Scalar S>
bool aligned(const S* p) {
  return reinterpret_cast<std::uintptr_t>(p) % alignof(S) == 0;
}

template <Scalar S>
S read(const S* base, std::size_t i, std::size_t stride) {
  S value;
  std::memcpy(&value, reinterpret_cast<const unsigned char*>(base) + i * stride, sizeof value);
  return value;
}

template <Scalar S>
std::size_t step(const SphereArrays<S>& a) {
  return a.stride_bytes == 0 ? sizeof(S) : a.stride_bytes;
}

}  // namespace

template <Scalar S>
int check(const SphereArrays<S>& a, const char* function) noexcept {
  constexpr bool kFloat = std::is_same_v<S, float>;
  if (a.count == 0) return SPHRAY_OK;  // no spheres: nothing is read, the arrays may be NULL
  if (a.cx == nullptr || a.cy == nullptr || a.cz == nullptr || a.r == nullptr)
    return fail(SPHRAY_ERROR_NULL_POINTER, function, "a sphere array (cx, cy, cz or r) is NULL");
  if (a.count > kMaxSpheres)
    return fail(SPHRAY_ERROR_TOO_LARGE, function, "count exceeds 2^32 - 1 spheres");
  if (a.stride_bytes % sizeof(S) != 0)
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function,
                kFloat ? "stride_bytes is not 0 nor a multiple of sizeof(float)"
                       : "stride_bytes is not 0 nor a multiple of sizeof(double)");
  if (a.stride_bytes != 0 && (a.count - 1) > PTRDIFF_MAX / a.stride_bytes)
    return fail(SPHRAY_ERROR_TOO_LARGE, function, "count * stride_bytes exceeds PTRDIFF_MAX");
  if (!aligned(a.cx) || !aligned(a.cy) || !aligned(a.cz) || !aligned(a.r))
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function,
                kFloat ? "a sphere array is not aligned for float"
                       : "a sphere array is not aligned for double");
  return SPHRAY_OK;
}

template <Scalar S>
BasicSphereSoA<S> copy(const SphereArrays<S>& a) {
  const std::size_t stride = step(a);
  BasicSphereSoA<S> spheres;
  spheres.reserve(a.count);
  for (std::size_t i = 0; i < a.count; ++i) {
    spheres.add({read(a.cx, i, stride), read(a.cy, i, stride), read(a.cz, i, stride)},
                read(a.r, i, stride));
  }
  return spheres;
}

template <Scalar S>
void overwrite(const SphereArrays<S>& a, BasicSphereSoA<S>& spheres) {
  const std::size_t stride = step(a);
  for (std::size_t i = 0; i < a.count; ++i) {
    spheres.set(static_cast<std::uint32_t>(i),
                {read(a.cx, i, stride), read(a.cy, i, stride), read(a.cz, i, stride)},
                read(a.r, i, stride));
  }
}

template int check(const SphereArrays<float>&, const char*) noexcept;
template int check(const SphereArrays<double>&, const char*) noexcept;
template SphereSoA copy(const SphereArrays<float>&);
template SphereSoAd copy(const SphereArrays<double>&);
template void overwrite(const SphereArrays<float>&, SphereSoA&);
template void overwrite(const SphereArrays<double>&, SphereSoAd&);

}  // namespace sphray::c_api
