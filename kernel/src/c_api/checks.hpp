// The argument checks the C functions share. Each returns SPHRAY_OK or the failure's status,
// with the calling thread's message set.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "c_api/convert.hpp"
#include "c_api/last_error.hpp"
#include "c_api/scene_handle.hpp"

namespace sphray::c_api {

/// The most elements a ray, hit or surface array of precision S may have: beyond it the array
/// would not fit in the address space (its byte size would exceed PTRDIFF_MAX), so the count is
/// a bug.
template <Scalar S = float>
inline constexpr std::size_t kMaxElements = PTRDIFF_MAX / sizeof(CSurface<S>);

inline int check_pointer(const void* p, const char* function, const char* name) noexcept {
  return p != nullptr ? SPHRAY_OK : fail(SPHRAY_ERROR_NULL_POINTER, function, name);
}

/// The calls return before this for a count of 0 (empty work: nothing read, nothing written).
template <Scalar S = float>
int check_count(std::size_t count, const char* function) noexcept {
  if (count > kMaxElements<S>)
    return fail(SPHRAY_ERROR_TOO_LARGE, function,
                std::is_same_v<S, float> ? "count exceeds PTRDIFF_MAX / 40"
                                         : "count exceeds PTRDIFF_MAX / 80");
  return SPHRAY_OK;
}

/// A live scene: not NULL, not released; of either precision.
inline int check_scene(const sphray_scene* scene, const char* function) noexcept {
  if (scene == nullptr) return fail(SPHRAY_ERROR_NULL_POINTER, function, "scene is NULL");
  if (scene->magic != sphray_scene::kLive || scene->scene == nullptr)
    return fail(SPHRAY_ERROR_RELEASED_SCENE, function, "scene was released");
  return SPHRAY_OK;
}

/// A live scene of precision S.
template <Scalar S>
int check_scene_in(const sphray_scene* scene, const char* function) noexcept {
  if (int status = check_scene(scene, function); status != SPHRAY_OK) return status;
  if (scene->scene->in<S>() != nullptr) return SPHRAY_OK;
  return fail(SPHRAY_ERROR_PRECISION, function,
              std::is_same_v<S, float>
                  ? "the scene holds doubles (sphray_scene_create_d): use the _d queries"
                  : "the scene holds floats (sphray_scene_create): use the queries without _d");
}

/// A query's arguments: a live scene of precision S, the two arrays (in_name: what the input
/// array holds, for the message), a count in range.
template <Scalar S = float>
int check_query(const sphray_scene* scene, const void* in, const void* out, std::size_t count,
                const char* function, const char* in_name = "rays is NULL") noexcept {
  int status = check_scene_in<S>(scene, function);
  if (status == SPHRAY_OK) status = check_pointer(in, function, in_name);
  if (status == SPHRAY_OK) status = check_pointer(out, function, "output array is NULL");
  if (status == SPHRAY_OK) status = check_count<S>(count, function);
  return status;
}

}  // namespace sphray::c_api
