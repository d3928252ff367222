// sphray_isa_supported, sphray_scene_create(_d), sphray_scene_isa, sphray_scene_precision,
// sphray_scene_refit(_d), sphray_scene_set_masks, sphray_scene_size, sphray_scene_release.
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <utility>

#include "c_api/checks.hpp"
#include "c_api/convert.hpp"
#include "c_api/last_error.hpp"
#include "c_api/scene_handle.hpp"
#include "c_api/sphere_arrays.hpp"
#include "dispatch/entry_table.hpp"

namespace sphray::c_api {
namespace {

// The renderer's crossover (render/src/frame/scene_queries.hpp, docs/bvh.md): from this many
// spheres on, a tree beats brute force.
constexpr std::size_t kBvhFromSpheres = 128;

// A scene's options (sphray_scene_args) with their defaults filled in.
struct SceneOptions {
  int accel = SPHRAY_ACCEL_AUTO;
  std::optional<Isa> isa;  // nothing: the process's choice
};

// This build has the instruction set's kernels and this machine runs them.
bool runs_here(Isa isa) {
  return detail::find_entries(isa) != nullptr;
}

// What create's args say (NULL: the defaults), or the failure.
int read_scene_args(const sphray_scene_args* args, const char* function, SceneOptions& options) {
  if (args == nullptr) return SPHRAY_OK;
  if (args->struct_size != sizeof(sphray_scene_args))
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function,
                "args->struct_size is not sizeof(sphray_scene_args)");
  if (args->accel != SPHRAY_ACCEL_AUTO && args->accel != SPHRAY_ACCEL_BRUTE &&
      args->accel != SPHRAY_ACCEL_BVH)
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function, "accel is not a SPHRAY_ACCEL_ value");
  options.accel = args->accel;
  if (args->isa == SPHRAY_ISA_AUTO) return SPHRAY_OK;
  options.isa = isa_from_c(args->isa);
  if (!options.isa)
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function, "isa is not a SPHRAY_ISA_ value");
  if (!runs_here(*options.isa))
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function,
                "isa cannot run here (see sphray_isa_supported)");
  // Brute force on a view runs on the process's instruction set; a scene that names one gets
  // a tree, which is laid out for it (docs/decisions.md, "The C API's second version").
  if (options.accel == SPHRAY_ACCEL_BRUTE)
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function,
                "an isa is chosen for a tree: use SPHRAY_ACCEL_AUTO or SPHRAY_ACCEL_BVH");
  return SPHRAY_OK;
}

// A tree from kBvhFromSpheres spheres on, or at every size when the scene names an
// instruction set: a small one is built flat and answers as brute force on that set's batches.
bool wants_bvh(const SceneOptions& options, std::size_t count) {
  return options.accel == SPHRAY_ACCEL_BVH ||
         (options.accel == SPHRAY_ACCEL_AUTO && (options.isa || count >= kBvhFromSpheres));
}

// Sphere i's mask from an array of stride_bytes steps (0: packed); memcpy reads it whatever the
// caller's structure type.
std::uint32_t mask_at(const std::uint32_t* masks, std::size_t stride_bytes, std::size_t i) {
  const std::size_t step = stride_bytes == 0 ? sizeof(std::uint32_t) : stride_bytes;
  std::uint32_t mask;
  std::memcpy(&mask, reinterpret_cast<const char*>(masks) + i * step, sizeof mask);
  return mask;
}

// spheres with the masks of `from` (same count); spheres without a mask array stay without one,
// so scenes that never had masks keep the unmasked queries.
template <Scalar S>
void copy_masks(const BasicSphereSoA<S>& from, BasicSphereSoA<S>& spheres) {
  for (std::uint32_t id = 0; id < from.size(); ++id) {
    if (from.mask(id) != kAllBits) spheres.set_mask(id, from.mask(id));
  }
}

// The same spheres without masks: a view of them takes the unmasked path again.
template <Scalar S>
BasicSphereSoA<S> unmasked(const BasicSphereSoA<S>& from) {
  BasicSphereSoA<S> spheres;
  spheres.reserve(from.size());
  for (std::uint32_t id = 0; id < from.size(); ++id)
    spheres.add(from.center(id), from.radius(id));
  return spheres;
}

// sphray_scene_create and _create_d.
template <Scalar S>
int create(const SphereArrays<S>& arrays, const sphray_scene_args* args, sphray_scene** out,
           const char* function) {
  SceneOptions options;
  if (int status = check_pointer(out, function, "out is NULL"); status != SPHRAY_OK) return status;
  if (int status = check(arrays, function); status != SPHRAY_OK) return status;
  if (int status = read_scene_args(args, function, options); status != SPHRAY_OK) return status;
  return guarded(function, [&] {
    BasicScene<S> scene;
    scene.spheres = copy(arrays);
    if (wants_bvh(options, arrays.count)) {
      const BasicSphereView<S> view = scene.spheres.view();
      if (options.isa)
        scene.bvh.emplace(view, *options.isa);
      else
        scene.bvh.emplace(view);
    }
    *out = adopt(new Scene{std::move(scene)});
    return SPHRAY_OK;
  });
}

// sphray_scene_refit and _refit_d.
template <Scalar S>
int refit(sphray_scene* handle, const SphereArrays<S>& arrays, const char* function) {
  if (int status = check_scene_in<S>(handle, function); status != SPHRAY_OK) return status;
  if (int status = check(arrays, function); status != SPHRAY_OK) return status;
  BasicScene<S>& scene = *handle->scene->in<S>();
  if (arrays.count != scene.spheres.size())
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function, "count differs from the scene's");
  return guarded(function, [&] {
    // The tree first, from a copy: if that cannot be made, the scene is left as it was. Then
    // the scene's own spheres (brute force's, and what surface() reads) are overwritten in
    // place, which cannot fail. Replacing them, as refit once did, freed the arrays under any
    // query still reading them: a crash (issue 30). In place, such a query sees each value old
    // or new, at no cost to queries (no lock, no reader count).
    if (scene.bvh) {
      BasicSphereSoA<S> spheres = copy(arrays);
      copy_masks(scene.spheres, spheres);
      scene.bvh->refit(spheres.view());
    }
    overwrite(arrays, scene.spheres);
    return SPHRAY_OK;
  });
}

}  // namespace
}  // namespace sphray::c_api

using namespace sphray::c_api;

extern "C" {

int sphray_isa_supported(int isa) {
  if (isa == SPHRAY_ISA_AUTO) return 1;
  const std::optional<sphray::Isa> named = isa_from_c(isa);
  return named && runs_here(*named) ? 1 : 0;
}

int sphray_scene_create(const float* cx, const float* cy, const float* cz, const float* r,
                        size_t count, size_t stride_bytes, const sphray_scene_args* args,
                        sphray_scene** out) {
  return create<float>({cx, cy, cz, r, count, stride_bytes}, args, out, "sphray_scene_create");
}

int sphray_scene_create_d(const double* cx, const double* cy, const double* cz, const double* r,
                          size_t count, size_t stride_bytes, const sphray_scene_args* args,
                          sphray_scene** out) {
  return create<double>({cx, cy, cz, r, count, stride_bytes}, args, out, "sphray_scene_create_d");
}

int sphray_scene_isa(const sphray_scene* handle, int* isa) {
  constexpr const char* kFunction = "sphray_scene_isa";
  if (int status = check_scene(handle, kFunction); status != SPHRAY_OK) return status;
  if (int status = check_pointer(isa, kFunction, "isa is NULL"); status != SPHRAY_OK) return status;
  *isa = handle->scene->visit(
      [](const auto& scene) { return to_c(scene.bvh ? scene.bvh->isa() : sphray::active_isa()); });
  return SPHRAY_OK;
}

int sphray_scene_precision(const sphray_scene* handle, int* precision) {
  constexpr const char* kFunction = "sphray_scene_precision";
  if (int status = check_scene(handle, kFunction); status != SPHRAY_OK) return status;
  if (int status = check_pointer(precision, kFunction, "precision is NULL"); status != SPHRAY_OK)
    return status;
  *precision = handle->scene->in<float>() ? SPHRAY_PRECISION_FLOAT : SPHRAY_PRECISION_DOUBLE;
  return SPHRAY_OK;
}

int sphray_scene_refit(sphray_scene* handle, const float* cx, const float* cy, const float* cz,
                       const float* r, size_t count, size_t stride_bytes) {
  return refit<float>(handle, {cx, cy, cz, r, count, stride_bytes}, "sphray_scene_refit");
}

int sphray_scene_refit_d(sphray_scene* handle, const double* cx, const double* cy, const double* cz,
                         const double* r, size_t count, size_t stride_bytes) {
  return refit<double>(handle, {cx, cy, cz, r, count, stride_bytes}, "sphray_scene_refit_d");
}

int sphray_scene_set_masks(sphray_scene* handle, const uint32_t* masks, size_t stride_bytes) {
  constexpr const char* kFunction = "sphray_scene_set_masks";
  if (int status = check_scene(handle, kFunction); status != SPHRAY_OK) return status;
  if (stride_bytes % sizeof(std::uint32_t) != 0)
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, kFunction, "stride_bytes is not a multiple of 4");
  if (reinterpret_cast<std::uintptr_t>(masks) % alignof(std::uint32_t) != 0)
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, kFunction, "masks is not aligned for uint32_t");
  return guarded(kFunction, [&] {
    handle->scene->visit([&](auto& scene) {
      // The new spheres are made first: if they cannot be, the scene is left as it was.
      auto spheres = unmasked(scene.spheres);
      if (masks != nullptr) {
        for (std::uint32_t id = 0; id < spheres.size(); ++id)
          spheres.set_mask(id, mask_at(masks, stride_bytes, id));
      }
      if (scene.bvh) scene.bvh->refit(spheres.view());
      scene.spheres = std::move(spheres);
    });
    return SPHRAY_OK;
  });
}

int sphray_scene_size(const sphray_scene* handle, size_t* count) {
  constexpr const char* kFunction = "sphray_scene_size";
  if (int status = check_scene(handle, kFunction); status != SPHRAY_OK) return status;
  if (int status = check_pointer(count, kFunction, "count is NULL"); status != SPHRAY_OK)
    return status;
  *count = handle->scene->visit([](const auto& scene) { return scene.spheres.size(); });
  return SPHRAY_OK;
}

int sphray_scene_release(sphray_scene* handle) {
  constexpr const char* kFunction = "sphray_scene_release";
  if (int status = check_scene(handle, kFunction); status != SPHRAY_OK) return status;
  retire(handle);
  return SPHRAY_OK;
}

}  // extern "C"
