// sphray_intersect, sphray_occluded (and their _parallel forms), sphray_intersect_arrays,
// sphray_surface, sphray_spawn: each converts between the C structs and sphray::Ray / Hit /
// Surface (or hands the arrays over as RayArrays / HitArrays) and calls the C++ API.
#include <algorithm>
#include <array>

#include "c_api/checks.hpp"
#include "c_api/convert.hpp"
#include "c_api/last_error.hpp"
#include "c_api/parallel_chunks.hpp"
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

}  // namespace
}  // namespace sphray::c_api

using namespace sphray::c_api;

extern "C" {

int sphray_intersect(const sphray_scene* scene, const sphray_ray* rays, sphray_hit* hits,
                     size_t count) {
  constexpr const char* kFunction = "sphray_intersect";
  if (count == 0) return check_scene(scene, kFunction);  // empty work
  if (int status = check_query(scene, rays, hits, count, kFunction); status != SPHRAY_OK)
    return status;
  return guarded(kFunction, [&] {
    intersect_range(*scene->scene, rays, nullptr, hits, 0, count);
    return SPHRAY_OK;
  });
}

int sphray_intersect_arrays(const sphray_scene* scene, const sphray_ray_arrays* rays, float* t,
                            uint32_t* id, size_t count) {
  constexpr const char* kFunction = "sphray_intersect_arrays";
  if (count == 0) return check_scene(scene, kFunction);  // empty work
  if (int status = check_query(scene, rays, t, count, kFunction); status != SPHRAY_OK)
    return status;
  if (int status = check_pointer(id, kFunction, "id is NULL"); status != SPHRAY_OK) return status;
  const bool complete = rays->ox != nullptr && rays->oy != nullptr && rays->oz != nullptr &&
                        rays->dx != nullptr && rays->dy != nullptr && rays->dz != nullptr;
  if (!complete)
    return fail(SPHRAY_ERROR_NULL_POINTER, kFunction, "a ray origin or direction array is NULL");
  return guarded(kFunction, [&] {
    const sphray::RayArrays in{rays->ox, rays->oy,   rays->oz,   rays->dx,   rays->dy,
                               rays->dz, rays->tmin, rays->tmax, rays->mask, count};
    const sphray::HitArrays out{t, id, count};
    scene->scene->answer([&](const auto& spheres) { sphray::intersect(spheres, in, out); });
    return SPHRAY_OK;
  });
}

int sphray_occluded(const sphray_scene* scene, const sphray_ray* rays, unsigned char* occluded,
                    size_t count) {
  constexpr const char* kFunction = "sphray_occluded";
  if (count == 0) return check_scene(scene, kFunction);  // empty work
  if (int status = check_query(scene, rays, occluded, count, kFunction); status != SPHRAY_OK)
    return status;
  return guarded(kFunction, [&] {
    occluded_range(*scene->scene, rays, nullptr, occluded, 0, count);
    return SPHRAY_OK;
  });
}

int sphray_intersect_masked(const sphray_scene* scene, const sphray_ray* rays,
                            const uint32_t* masks, sphray_hit* hits, size_t count) {
  constexpr const char* kFunction = "sphray_intersect_masked";
  if (count == 0) return check_scene(scene, kFunction);  // empty work
  if (int status = check_query(scene, rays, hits, count, kFunction); status != SPHRAY_OK)
    return status;
  if (int status = check_pointer(masks, kFunction, "masks is NULL"); status != SPHRAY_OK)
    return status;
  return guarded(kFunction, [&] {
    intersect_range(*scene->scene, rays, masks, hits, 0, count);
    return SPHRAY_OK;
  });
}

int sphray_occluded_masked(const sphray_scene* scene, const sphray_ray* rays, const uint32_t* masks,
                           unsigned char* occluded, size_t count) {
  constexpr const char* kFunction = "sphray_occluded_masked";
  if (count == 0) return check_scene(scene, kFunction);  // empty work
  if (int status = check_query(scene, rays, occluded, count, kFunction); status != SPHRAY_OK)
    return status;
  if (int status = check_pointer(masks, kFunction, "masks is NULL"); status != SPHRAY_OK)
    return status;
  return guarded(kFunction, [&] {
    occluded_range(*scene->scene, rays, masks, occluded, 0, count);
    return SPHRAY_OK;
  });
}

int sphray_intersect_parallel(const sphray_scene* scene, const sphray_ray* rays, sphray_hit* hits,
                              size_t count, unsigned threads) {
  constexpr const char* kFunction = "sphray_intersect_parallel";
  if (count == 0) return check_scene(scene, kFunction);  // empty work
  if (int status = check_query(scene, rays, hits, count, kFunction); status != SPHRAY_OK)
    return status;
  return guarded(kFunction, [&] {
    const Scene& s = *scene->scene;
    parallel_chunks(count, threads, [&](std::size_t begin, std::size_t end) {
      intersect_range(s, rays, nullptr, hits, begin, end);
    });
    return SPHRAY_OK;
  });
}

int sphray_occluded_parallel(const sphray_scene* scene, const sphray_ray* rays,
                             unsigned char* occluded, size_t count, unsigned threads) {
  constexpr const char* kFunction = "sphray_occluded_parallel";
  if (count == 0) return check_scene(scene, kFunction);  // empty work
  if (int status = check_query(scene, rays, occluded, count, kFunction); status != SPHRAY_OK)
    return status;
  return guarded(kFunction, [&] {
    const Scene& s = *scene->scene;
    parallel_chunks(count, threads, [&](std::size_t begin, std::size_t end) {
      occluded_range(s, rays, nullptr, occluded, begin, end);
    });
    return SPHRAY_OK;
  });
}

int sphray_surface(const sphray_scene* scene, const sphray_ray* rays, const sphray_hit* hits,
                   sphray_hit_surface* surfaces, size_t count) {
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

int sphray_spawn(const sphray_hit_surface* surfaces, const float* dirs, sphray_ray* rays,
                 size_t count) {
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
