// sphray_intersect, sphray_occluded, sphray_intersect_arrays, sphray_surface, sphray_spawn: each
// converts between the C structs and sphray::Ray / Hit / Surface (or hands the arrays over as
// RayArrays / HitArrays) and calls the C++ API, on the threads its sphray_query_args ask for.
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
template <class Answer, class Out, class Query, class ToC>
void stream_range(const Scene& scene, const sphray_ray* rays, const std::uint32_t* masks, Out* out,
                  std::size_t begin, std::size_t end, Query query, ToC to_c) {
  std::array<Ray, kStreamChunk> in;
  std::array<Answer, kStreamChunk> answers;
  for (std::size_t start = begin; start < end; start += kStreamChunk) {
    const std::size_t n = std::min(kStreamChunk, end - start);
    for (std::size_t i = 0; i < n; ++i)
      in[i] = to_ray(rays, masks, start + i);
    const std::span<const Ray> batch(in.data(), n);
    const std::span<Answer> results(answers.data(), n);
    scene.answer([&](const auto& spheres) { query(spheres, batch, results); });
    for (std::size_t i = 0; i < n; ++i)
      out[start + i] = to_c(answers[i]);
  }
}

// Closest hits through intersect(.., rays, hits).
void intersect_range(const Scene& scene, const sphray_ray* rays, const std::uint32_t* masks,
                     sphray_hit* hits, std::size_t begin, std::size_t end) {
  stream_range<Hit>(
      scene, rays, masks, hits, begin, end,
      [](const auto& spheres, std::span<const Ray> in, std::span<Hit> out) {
        sphray::intersect(spheres, in, out);
      },
      [](const Hit& h) {
        return sphray_hit{h.t, h.id};
      });
}

// Occlusion through occluded(.., rays, blocked): on a tree, coherent rays (shadow rays towards
// one light) go in packets.
void occluded_range(const Scene& scene, const sphray_ray* rays, const std::uint32_t* masks,
                    unsigned char* occluded, std::size_t begin, std::size_t end) {
  stream_range<bool>(
      scene, rays, masks, occluded, begin, end,
      [](const auto& spheres, std::span<const Ray> in, std::span<bool> out) {
        sphray::occluded(spheres, in, out);
      },
      [](bool blocked) -> unsigned char { return blocked ? 1 : 0; });
}

// The arrays' rays [begin, end) as RayArrays, with their masks (null: every bit).
sphray::RayArrays ray_range(const sphray_ray_arrays& rays, const std::uint32_t* masks,
                            std::size_t begin, std::size_t end) {
  auto from = [begin](const auto* array) { return array == nullptr ? nullptr : array + begin; };
  return {from(rays.ox), from(rays.oy),   from(rays.oz),   from(rays.dx), from(rays.dy),
          from(rays.dz), from(rays.tmin), from(rays.tmax), from(masks),   end - begin};
}

}  // namespace
}  // namespace sphray::c_api

using namespace sphray::c_api;

extern "C" {

int sphray_intersect(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                     sphray_hit* hits, const sphray_query_args* args) {
  constexpr const char* kFunction = "sphray_intersect";
  QueryOptions options;
  const int status = check_batch(scene, rays, hits, count, args, Inputs::rays, kFunction, options);
  if (status != SPHRAY_OK || count == 0) return status;
  return run_batch(kFunction, count, options, [&](unsigned, std::size_t begin, std::size_t end) {
    intersect_range(*scene->scene, rays, options.masks, hits, begin, end);
  });
}

int sphray_occluded(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                    unsigned char* occluded, const sphray_query_args* args) {
  constexpr const char* kFunction = "sphray_occluded";
  QueryOptions options;
  const int status =
      check_batch(scene, rays, occluded, count, args, Inputs::rays, kFunction, options);
  if (status != SPHRAY_OK || count == 0) return status;
  return run_batch(kFunction, count, options, [&](unsigned, std::size_t begin, std::size_t end) {
    occluded_range(*scene->scene, rays, options.masks, occluded, begin, end);
  });
}

int sphray_intersect_arrays(const sphray_scene* scene, const sphray_ray_arrays* rays, size_t count,
                            float* t, uint32_t* id, const sphray_query_args* args) {
  constexpr const char* kFunction = "sphray_intersect_arrays";
  QueryOptions options;
  int status = check_batch(scene, rays, t, count, args, Inputs::rays, kFunction, options);
  if (status != SPHRAY_OK || count == 0) return status;
  if (status = check_pointer(id, kFunction, "id is NULL"); status != SPHRAY_OK) return status;
  const bool complete = rays->ox != nullptr && rays->oy != nullptr && rays->oz != nullptr &&
                        rays->dx != nullptr && rays->dy != nullptr && rays->dz != nullptr;
  if (!complete)
    return fail(SPHRAY_ERROR_NULL_POINTER, kFunction, "a ray origin or direction array is NULL");
  return run_batch(kFunction, count, options, [&](unsigned, std::size_t begin, std::size_t end) {
    const sphray::RayArrays in = ray_range(*rays, options.masks, begin, end);
    const sphray::HitArrays out{t + begin, id + begin, end - begin};
    scene->scene->answer([&](const auto& spheres) { sphray::intersect(spheres, in, out); });
  });
}

int sphray_surface(const sphray_scene* scene, const sphray_ray* rays, const sphray_hit* hits,
                   size_t count, sphray_hit_surface* surfaces) {
  constexpr const char* kFunction = "sphray_surface";
  if (count == 0) return check_scene(scene, kFunction);  // empty work
  if (int status = check_query(scene, rays, surfaces, count, kFunction); status != SPHRAY_OK)
    return status;
  if (int status = check_pointer(hits, kFunction, "hits is NULL"); status != SPHRAY_OK)
    return status;
  return guarded(kFunction, [&] {
    const sphray::SphereView view = scene->scene->spheres.view();
    for (std::size_t i = 0; i < count; ++i) {
      const sphray::Hit hit{hits[i].t, hits[i].id};
      surfaces[i] = to_c(sphray::surface(view, to_ray(rays[i]), hit));
    }
    return SPHRAY_OK;
  });
}

int sphray_spawn(const sphray_hit_surface* surfaces, const float* dirs, size_t count,
                 sphray_ray* rays) {
  constexpr const char* kFunction = "sphray_spawn";
  if (count == 0) return SPHRAY_OK;  // empty work: nothing read, nothing written
  int status = check_pointer(surfaces, kFunction, "surfaces is NULL");
  if (status == SPHRAY_OK) status = check_pointer(dirs, kFunction, "dirs is NULL");
  if (status == SPHRAY_OK) status = check_pointer(rays, kFunction, "rays is NULL");
  if (status == SPHRAY_OK) status = check_count(count, kFunction);
  if (status != SPHRAY_OK) return status;
  return guarded(kFunction, [&] {
    for (std::size_t i = 0; i < count; ++i) {
      const sphray::Vec3 dir{dirs[3 * i], dirs[3 * i + 1], dirs[3 * i + 2]};
      rays[i] = to_c(sphray::spawn(from_c(surfaces[i]), dir));
    }
    return SPHRAY_OK;
  });
}

}  // extern "C"
