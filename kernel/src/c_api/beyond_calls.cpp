// sphray_intersect_all, sphray_intersect_nearest, sphray_count_hits, sphray_nearest,
// sphray_inside, sphray_overlapping:
// the queries beyond the closest hit (docs/queries.md), converted to and from the C structs,
// answered by the C++ API.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <span>
#include <vector>

#include "c_api/checks.hpp"
#include "c_api/convert.hpp"
#include "c_api/last_error.hpp"
#include "c_api/scene_handle.hpp"

namespace sphray::c_api {
namespace {

// Up to this many crossings per ray go through a buffer on the stack; more, through one on the
// heap, made once per call.
constexpr std::size_t kStackSlots = 64;

// Which crossings a call wants: every one, counted (intersect_all), or the nearest slots alone
// (intersect_nearest).
enum class Crossings { all, nearest };

// The crossings of one ray into its slots of hits and exits, through slots and flags (the C++
// types: sphray_hit and unsigned char are other types); returns the total (all) or how many
// were written (nearest).
std::size_t crossings(const Scene& scene, Crossings which, const Ray& ray, std::span<Hit> slots,
                      std::span<bool> flags, sphray_hit* hits, unsigned char* exits) {
  const std::size_t total = scene.answer([&](const auto& spheres) {
    return which == Crossings::all ? sphray::intersect_all(spheres, ray, slots, flags)
                                   : sphray::intersect_nearest(spheres, ray, slots, flags);
  });
  for (std::size_t k = 0; k < std::min(slots.size(), total); ++k) {
    hits[k] = {slots[k].t, slots[k].id};
    if (exits != nullptr) exits[k] = flags[k] ? 1 : 0;
  }
  return total;
}

int intersect_all(const sphray_scene* scene, Crossings which, const sphray_ray* rays,
                  const std::uint32_t* masks, size_t count, size_t max_hits, sphray_hit* hits,
                  unsigned char* exits, size_t* counts, const char* function) {
  if (count == 0) return check_scene(scene, function);  // empty work
  if (int status = check_query(scene, rays, counts, count, function); status != SPHRAY_OK)
    return status;
  if (max_hits > 0) {
    if (int status = check_pointer(hits, function, "hits is NULL"); status != SPHRAY_OK)
      return status;
    if (max_hits > kMaxElements / count)
      return fail(SPHRAY_ERROR_TOO_LARGE, function, "count * max_hits exceeds the address space");
  }
  return guarded(function, [&] {
    std::array<sphray::Hit, kStackSlots> stack_slots;
    std::array<bool, kStackSlots> stack_flags;
    std::vector<sphray::Hit> heap_slots;
    std::unique_ptr<bool[]> heap_flags;
    std::span<sphray::Hit> slots(stack_slots.data(), std::min(max_hits, kStackSlots));
    std::span<bool> flags(stack_flags.data(), std::min(max_hits, kStackSlots));
    if (max_hits > kStackSlots) {
      heap_slots.resize(max_hits);
      heap_flags = std::make_unique<bool[]>(max_hits);
      slots = heap_slots;
      flags = std::span<bool>(heap_flags.get(), max_hits);
    }
    for (std::size_t i = 0; i < count; ++i) {
      counts[i] = crossings(*scene->scene, which, to_ray(rays, masks, i), slots, flags,
                            hits == nullptr ? nullptr : hits + i * max_hits,
                            exits == nullptr ? nullptr : exits + i * max_hits);
    }
    return SPHRAY_OK;
  });
}

// The masked forms: the masks array is required, the rest as the plain forms check it.
int intersect_all_masked(const sphray_scene* scene, Crossings which, const sphray_ray* rays,
                         const std::uint32_t* masks, size_t count, size_t max_hits,
                         sphray_hit* hits, unsigned char* exits, size_t* counts,
                         const char* function) {
  if (count == 0) return check_scene(scene, function);  // empty work
  if (int status = check_pointer(masks, function, "masks is NULL"); status != SPHRAY_OK)
    return status;
  return intersect_all(scene, which, rays, masks, count, max_hits, hits, exits, counts, function);
}

int count_hits(const sphray_scene* scene, const sphray_ray* rays, const std::uint32_t* masks,
               size_t* counts, size_t count, const char* function) {
  if (count == 0) return check_scene(scene, function);  // empty work
  if (int status = check_query(scene, rays, counts, count, function); status != SPHRAY_OK)
    return status;
  return guarded(function, [&] {
    scene->scene->answer([&](const auto& spheres) {
      for (std::size_t i = 0; i < count; ++i)
        counts[i] = sphray::count_hits(spheres, to_ray(rays, masks, i));
    });
    return SPHRAY_OK;
  });
}

}  // namespace
}  // namespace sphray::c_api

using namespace sphray::c_api;

extern "C" {

int sphray_intersect_all(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                         size_t max_hits, sphray_hit* hits, unsigned char* exits, size_t* counts) {
  return intersect_all(scene, Crossings::all, rays, nullptr, count, max_hits, hits, exits, counts,
                       "sphray_intersect_all");
}

int sphray_intersect_all_masked(const sphray_scene* scene, const sphray_ray* rays,
                                const uint32_t* masks, size_t count, size_t max_hits,
                                sphray_hit* hits, unsigned char* exits, size_t* counts) {
  return intersect_all_masked(scene, Crossings::all, rays, masks, count, max_hits, hits, exits,
                              counts, "sphray_intersect_all_masked");
}

int sphray_intersect_nearest(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                             size_t max_hits, sphray_hit* hits, unsigned char* exits,
                             size_t* counts) {
  return intersect_all(scene, Crossings::nearest, rays, nullptr, count, max_hits, hits, exits,
                       counts, "sphray_intersect_nearest");
}

int sphray_intersect_nearest_masked(const sphray_scene* scene, const sphray_ray* rays,
                                    const uint32_t* masks, size_t count, size_t max_hits,
                                    sphray_hit* hits, unsigned char* exits, size_t* counts) {
  return intersect_all_masked(scene, Crossings::nearest, rays, masks, count, max_hits, hits, exits,
                              counts, "sphray_intersect_nearest_masked");
}

int sphray_count_hits(const sphray_scene* scene, const sphray_ray* rays, size_t* counts,
                      size_t count) {
  return count_hits(scene, rays, nullptr, counts, count, "sphray_count_hits");
}

int sphray_count_hits_masked(const sphray_scene* scene, const sphray_ray* rays,
                             const uint32_t* masks, size_t* counts, size_t count) {
  constexpr const char* kFunction = "sphray_count_hits_masked";
  if (count == 0) return check_scene(scene, kFunction);  // empty work
  if (int status = check_pointer(masks, kFunction, "masks is NULL"); status != SPHRAY_OK)
    return status;
  return count_hits(scene, rays, masks, counts, count, kFunction);
}

int sphray_nearest(const sphray_scene* scene, const float* points, float max_distance,
                   sphray_nearest_sphere* out, size_t count) {
  constexpr const char* kFunction = "sphray_nearest";
  if (count == 0) return check_scene(scene, kFunction);  // empty work
  if (int status = check_query(scene, points, out, count, kFunction); status != SPHRAY_OK)
    return status;
  return guarded(kFunction, [&] {
    scene->scene->answer([&](const auto& spheres) {
      for (std::size_t i = 0; i < count; ++i) {
        const sphray::Nearest n = sphray::nearest(spheres, point_at(points, i), max_distance);
        out[i] = {n.id, n.distance, n.point.x, n.point.y, n.point.z};
      }
    });
    return SPHRAY_OK;
  });
}

int sphray_inside(const sphray_scene* scene, const float* points, unsigned char* inside,
                  size_t count) {
  constexpr const char* kFunction = "sphray_inside";
  if (count == 0) return check_scene(scene, kFunction);  // empty work
  if (int status = check_query(scene, points, inside, count, kFunction); status != SPHRAY_OK)
    return status;
  return guarded(kFunction, [&] {
    scene->scene->answer([&](const auto& spheres) {
      for (std::size_t i = 0; i < count; ++i)
        inside[i] = sphray::inside(spheres, point_at(points, i)) ? 1 : 0;
    });
    return SPHRAY_OK;
  });
}

int sphray_overlapping(const sphray_scene* scene, const float* centre, float radius, uint32_t* ids,
                       size_t capacity, size_t* total) {
  constexpr const char* kFunction = "sphray_overlapping";
  int status = check_scene(scene, kFunction);
  if (status == SPHRAY_OK) status = check_pointer(centre, kFunction, "centre is NULL");
  if (status == SPHRAY_OK) status = check_pointer(total, kFunction, "total is NULL");
  if (status == SPHRAY_OK && capacity > 0) status = check_pointer(ids, kFunction, "ids is NULL");
  if (status == SPHRAY_OK && capacity > kMaxElements)
    status = fail(SPHRAY_ERROR_TOO_LARGE, kFunction, "capacity exceeds the address space");
  if (status != SPHRAY_OK) return status;
  return guarded(kFunction, [&] {
    const sphray::Vec3 c{centre[0], centre[1], centre[2]};
    const std::span<std::uint32_t> out(ids, capacity);
    *total = scene->scene->answer(
        [&](const auto& spheres) { return sphray::overlapping(spheres, c, radius, out); });
    return SPHRAY_OK;
  });
}

}  // extern "C"
