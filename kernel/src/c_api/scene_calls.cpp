// sphray_scene_create, sphray_scene_refit, sphray_scene_size, sphray_scene_release.
#include <memory>

#include "c_api/checks.hpp"
#include "c_api/last_error.hpp"
#include "c_api/scene_handle.hpp"
#include "c_api/sphere_arrays.hpp"

namespace sphray::c_api {
namespace {

// The renderer's crossover (render/src/scene_queries.hpp, docs/bvh.md): from this many
// spheres on, a tree beats brute force.
constexpr std::size_t kBvhFromSpheres = 128;

bool wants_bvh(int accel, std::size_t count) {
  return accel == SPHRAY_ACCEL_BVH || (accel == SPHRAY_ACCEL_AUTO && count >= kBvhFromSpheres);
}

}  // namespace
}  // namespace sphray::c_api

using namespace sphray::c_api;

extern "C" {

int sphray_scene_create(const float* cx, const float* cy, const float* cz, const float* r,
                        size_t count, size_t stride_bytes, int accel, sphray_scene** out) {
  constexpr const char* kFunction = "sphray_scene_create";
  const SphereArrays arrays{cx, cy, cz, r, count, stride_bytes};
  if (int status = check_pointer(out, kFunction, "out is NULL"); status != SPHRAY_OK) return status;
  if (int status = check(arrays, kFunction); status != SPHRAY_OK) return status;
  if (accel != SPHRAY_ACCEL_AUTO && accel != SPHRAY_ACCEL_BRUTE && accel != SPHRAY_ACCEL_BVH)
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, kFunction, "accel is not a SPHRAY_ACCEL_ value");
  return guarded(kFunction, [&] {
    auto scene = std::make_unique<Scene>();
    scene->spheres = copy(arrays);
    if (wants_bvh(accel, count)) scene->bvh.emplace(scene->spheres.view());
    *out = adopt(scene.release());
    return SPHRAY_OK;
  });
}

int sphray_scene_refit(sphray_scene* handle, const float* cx, const float* cy, const float* cz,
                       const float* r, size_t count, size_t stride_bytes) {
  constexpr const char* kFunction = "sphray_scene_refit";
  const SphereArrays arrays{cx, cy, cz, r, count, stride_bytes};
  if (int status = check_scene(handle, kFunction); status != SPHRAY_OK) return status;
  if (int status = check(arrays, kFunction); status != SPHRAY_OK) return status;
  Scene& scene = *handle->scene;
  if (count != scene.spheres.size())
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, kFunction, "count differs from the scene's");
  return guarded(kFunction, [&] {
    // The copy is made first: if it cannot be, the scene is left as it was.
    sphray::SphereSoA spheres = copy(arrays);
    if (scene.bvh) scene.bvh->refit(spheres.view());
    scene.spheres = std::move(spheres);
    return SPHRAY_OK;
  });
}

int sphray_scene_size(const sphray_scene* handle, size_t* count) {
  constexpr const char* kFunction = "sphray_scene_size";
  if (int status = check_scene(handle, kFunction); status != SPHRAY_OK) return status;
  if (int status = check_pointer(count, kFunction, "count is NULL"); status != SPHRAY_OK)
    return status;
  *count = handle->scene->spheres.size();
  return SPHRAY_OK;
}

int sphray_scene_release(sphray_scene* handle) {
  constexpr const char* kFunction = "sphray_scene_release";
  if (int status = check_scene(handle, kFunction); status != SPHRAY_OK) return status;
  retire(handle);
  return SPHRAY_OK;
}

}  // extern "C"
