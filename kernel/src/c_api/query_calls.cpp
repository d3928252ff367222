// sphray_intersect, sphray_occluded, sphray_intersect_arrays, sphray_surface, sphray_spawn, and
// their _d forms: each converts between the C structs and sphray::Ray /
// Hit / Surface in their precision (or hands the arrays over as RayArrays / HitArrays) and calls
// the C++ API, on the threads its sphray_query_args ask for.
#include <algorithm>
#include <array>

#include "c_api/batch_call.hpp"
#include "c_api/checks.hpp"
#include "c_api/convert.hpp"
#include "c_api/last_error.hpp"
#include "c_api/scene_handle.hpp"

namespace sphray::c_api {
namespace {

// Rays converted at a time, on the stack: a query allocates nothing.
constexpr std::size_t kStreamChunk = 256;

// out[i] for i in [begin, end) from a C++ stream call, query(spheres, rays, answers), a stack
// chunk at a time; to_c turns each answer into its C form. masks: null, or one per ray.
template <class Answer, Scalar S, class Out, class Query, class ToC>
void stream_range(const BasicScene<S>& scene, const CRay<S>* rays, const std::uint32_t* masks,
                  Out* out, std::size_t begin, std::size_t end, Query query, ToC to_c) {
  std::array<BasicRay<S>, kStreamChunk> in;
  std::array<Answer, kStreamChunk> answers;
  for (std::size_t start = begin; start < end; start += kStreamChunk) {
    const std::size_t n = std::min(kStreamChunk, end - start);
    for (std::size_t i = 0; i < n; ++i)
      in[i] = to_ray(rays, masks, start + i);
    const std::span<const BasicRay<S>> batch(in.data(), n);
    const std::span<Answer> results(answers.data(), n);
    scene.answer([&](const auto& spheres) { query(spheres, batch, results); });
    for (std::size_t i = 0; i < n; ++i)
      out[start + i] = to_c(answers[i]);
  }
}

// sphray_intersect and _intersect_d: closest hits through intersect(.., rays, hits).
template <Scalar S>
int closest_hits(const sphray_scene* scene, const CRay<S>* rays, std::size_t count, CHit<S>* hits,
                 const sphray_query_args* args, const char* function) {
  QueryOptions options;
  const int status =
      check_batch<S>(scene, rays, hits, count, args, Inputs::rays, function, options);
  if (status != SPHRAY_OK || count == 0) return status;
  return run_batch(function, count, options, [&](unsigned, std::size_t begin, std::size_t end) {
    stream_range<BasicHit<S>>(
        *scene->scene->in<S>(), rays, options.masks, hits, begin, end,
        [](const auto& spheres, auto in, auto out) { sphray::intersect(spheres, in, out); },
        [](const BasicHit<S>& h) { return to_c(h); });
  });
}

// sphray_occluded and _occluded_d: occlusion through occluded(.., rays, blocked); on a tree,
// coherent rays (shadow rays towards one light) go in packets.
template <Scalar S>
int occlusions(const sphray_scene* scene, const CRay<S>* rays, std::size_t count,
               unsigned char* blocked, const sphray_query_args* args, const char* function) {
  QueryOptions options;
  const int status =
      check_batch<S>(scene, rays, blocked, count, args, Inputs::rays, function, options);
  if (status != SPHRAY_OK || count == 0) return status;
  return run_batch(function, count, options, [&](unsigned, std::size_t begin, std::size_t end) {
    stream_range<bool>(
        *scene->scene->in<S>(), rays, options.masks, blocked, begin, end,
        [](const auto& spheres, auto in, auto out) { sphray::occluded(spheres, in, out); },
        [](bool b) -> unsigned char { return b ? 1 : 0; });
  });
}

// sphray_surface and _surface_d.
template <Scalar S>
int surfaces_at(const sphray_scene* scene, const CRay<S>* rays, const CHit<S>* hits,
                std::size_t count, CSurface<S>* surfaces, const char* function) {
  if (count == 0) return check_scene_in<S>(scene, function);  // empty work
  if (int status = check_query<S>(scene, rays, surfaces, count, function); status != SPHRAY_OK)
    return status;
  if (int status = check_pointer(hits, function, "hits is NULL"); status != SPHRAY_OK)
    return status;
  return guarded(function, [&] {
    const BasicSphereView<S> view = scene->scene->in<S>()->spheres.view();
    for (std::size_t i = 0; i < count; ++i)
      surfaces[i] = to_c(sphray::surface(view, to_ray(rays[i]), from_c(hits[i])));
    return SPHRAY_OK;
  });
}

// sphray_spawn and _spawn_d.
template <Scalar S>
int spawned_rays(const CSurface<S>* surfaces, const S* dirs, std::size_t count, CRay<S>* rays,
                 const char* function) {
  if (count == 0) return SPHRAY_OK;  // empty work: nothing read, nothing written
  int status = check_pointer(surfaces, function, "surfaces is NULL");
  if (status == SPHRAY_OK) status = check_pointer(dirs, function, "dirs is NULL");
  if (status == SPHRAY_OK) status = check_pointer(rays, function, "rays is NULL");
  if (status == SPHRAY_OK) status = check_count<S>(count, function);
  if (status != SPHRAY_OK) return status;
  return guarded(function, [&] {
    for (std::size_t i = 0; i < count; ++i) {
      const BasicVec3<S> dir{dirs[3 * i], dirs[3 * i + 1], dirs[3 * i + 2]};
      rays[i] = to_c(sphray::spawn(from_c(surfaces[i]), dir));
    }
    return SPHRAY_OK;
  });
}

// The arrays' rays [begin, end) as RayArrays in precision S, with their masks (null: every
// bit). CArrays: sphray_ray_arrays (float) or sphray_ray_arrays_d (double).
template <Scalar S, class CArrays>
BasicRayArrays<S> ray_range(const CArrays& rays, const std::uint32_t* masks, std::size_t begin,
                            std::size_t end) {
  auto from = [begin](const auto* array) { return array == nullptr ? nullptr : array + begin; };
  return BasicRayArrays<S>{from(rays.ox), from(rays.oy), from(rays.oz),   from(rays.dx),
                           from(rays.dy), from(rays.dz), from(rays.tmin), from(rays.tmax),
                           from(masks),   end - begin};
}

// sphray_intersect_arrays and its _d form: the closest hits of rays given as arrays, handed to
// the C++ stream call of the scene's precision a range per thread.
template <Scalar S, class CArrays>
int closest_hits_of_arrays(const sphray_scene* scene, const CArrays* rays, std::size_t count, S* t,
                           std::uint32_t* id, const sphray_query_args* args, const char* function) {
  QueryOptions options;
  int status = check_batch<S>(scene, rays, t, count, args, Inputs::rays, function, options);
  if (status != SPHRAY_OK || count == 0) return status;
  if (status = check_pointer(id, function, "id is NULL"); status != SPHRAY_OK) return status;
  const bool complete = rays->ox != nullptr && rays->oy != nullptr && rays->oz != nullptr &&
                        rays->dx != nullptr && rays->dy != nullptr && rays->dz != nullptr;
  if (!complete)
    return fail(SPHRAY_ERROR_NULL_POINTER, function, "a ray origin or direction array is NULL");
  return run_batch(function, count, options, [&](unsigned, std::size_t begin, std::size_t end) {
    const BasicRayArrays<S> in = ray_range<S>(*rays, options.masks, begin, end);
    const BasicHitArrays<S> out{t + begin, id + begin, end - begin};
    scene->scene->in<S>()->answer(
        [&](const auto& spheres) { sphray::intersect(spheres, in, out); });
  });
}

}  // namespace
}  // namespace sphray::c_api

using namespace sphray::c_api;

extern "C" {

int sphray_intersect(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                     sphray_hit* hits, const sphray_query_args* args) {
  return closest_hits<float>(scene, rays, count, hits, args, "sphray_intersect");
}

int sphray_intersect_d(const sphray_scene* scene, const sphray_ray_d* rays, size_t count,
                       sphray_hit_d* hits, const sphray_query_args* args) {
  return closest_hits<double>(scene, rays, count, hits, args, "sphray_intersect_d");
}

int sphray_occluded(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                    unsigned char* occluded, const sphray_query_args* args) {
  return occlusions<float>(scene, rays, count, occluded, args, "sphray_occluded");
}

int sphray_occluded_d(const sphray_scene* scene, const sphray_ray_d* rays, size_t count,
                      unsigned char* occluded, const sphray_query_args* args) {
  return occlusions<double>(scene, rays, count, occluded, args, "sphray_occluded_d");
}

int sphray_intersect_arrays(const sphray_scene* scene, const sphray_ray_arrays* rays, size_t count,
                            float* t, uint32_t* id, const sphray_query_args* args) {
  return closest_hits_of_arrays(scene, rays, count, t, id, args, "sphray_intersect_arrays");
}

int sphray_intersect_arrays_d(const sphray_scene* scene, const sphray_ray_arrays_d* rays,
                              size_t count, double* t, uint32_t* id,
                              const sphray_query_args* args) {
  return closest_hits_of_arrays(scene, rays, count, t, id, args, "sphray_intersect_arrays_d");
}

int sphray_surface(const sphray_scene* scene, const sphray_ray* rays, const sphray_hit* hits,
                   size_t count, sphray_hit_surface* surfaces) {
  return surfaces_at<float>(scene, rays, hits, count, surfaces, "sphray_surface");
}

int sphray_surface_d(const sphray_scene* scene, const sphray_ray_d* rays, const sphray_hit_d* hits,
                     size_t count, sphray_hit_surface_d* surfaces) {
  return surfaces_at<double>(scene, rays, hits, count, surfaces, "sphray_surface_d");
}

int sphray_spawn(const sphray_hit_surface* surfaces, const float* dirs, size_t count,
                 sphray_ray* rays) {
  return spawned_rays<float>(surfaces, dirs, count, rays, "sphray_spawn");
}

int sphray_spawn_d(const sphray_hit_surface_d* surfaces, const double* dirs, size_t count,
                   sphray_ray_d* rays) {
  return spawned_rays<double>(surfaces, dirs, count, rays, "sphray_spawn_d");
}

}  // extern "C"
