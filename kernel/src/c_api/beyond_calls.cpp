// sphray_intersect_all, sphray_count_hits, sphray_nearest, sphray_inside, sphray_overlapping:
// the queries beyond the closest hit (docs/queries.md), converted to and from the C structs,
// answered by the C++ API.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <span>
#include <vector>

#include "c_api/checks.hpp"
#include "c_api/last_error.hpp"
#include "c_api/scene_handle.hpp"

namespace sphray::c_api {
namespace {

// Up to this many crossings per ray go through a buffer on the stack; more, through one on the
// heap, made once per call.
constexpr std::size_t kStackSlots = 64;

Ray to_ray(const sphray_ray& r) {
  return {{r.ox, r.oy, r.oz}, {r.dx, r.dy, r.dz}, r.tmin, r.tmax};
}

Vec3 point_at(const float* points, std::size_t i) {
  return {points[3 * i], points[3 * i + 1], points[3 * i + 2]};
}

// The crossings of one ray into its slots of hits and exits, through slots and flags (the C++
// types: sphray_hit and unsigned char are other types); returns the total.
std::size_t crossings(const Scene& scene, const Ray& ray, std::span<Hit> slots,
                      std::span<bool> flags, sphray_hit* hits, unsigned char* exits) {
  const std::size_t total = scene.bvh
                                ? sphray::intersect_all(*scene.bvh, ray, slots, flags)
                                : sphray::intersect_all(scene.spheres.view(), ray, slots, flags);
  for (std::size_t k = 0; k < std::min(slots.size(), total); ++k) {
    hits[k] = {slots[k].t, slots[k].id};
    if (exits != nullptr) exits[k] = flags[k] ? 1 : 0;
  }
  return total;
}

}  // namespace
}  // namespace sphray::c_api

using namespace sphray::c_api;

extern "C" {

int sphray_intersect_all(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                         size_t max_hits, sphray_hit* hits, unsigned char* exits, size_t* counts) {
  constexpr const char* kFunction = "sphray_intersect_all";
  if (int status = check_query(scene, rays, counts, count, kFunction); status != SPHRAY_OK)
    return status;
  if (max_hits > 0) {
    if (int status = check_pointer(hits, kFunction, "hits is NULL"); status != SPHRAY_OK)
      return status;
    if (max_hits > kMaxElements / count)
      return fail(SPHRAY_ERROR_TOO_LARGE, kFunction, "count * max_hits exceeds the address space");
  }
  return guarded(kFunction, [&] {
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
      counts[i] = crossings(*scene->scene, to_ray(rays[i]), slots, flags,
                            hits == nullptr ? nullptr : hits + i * max_hits,
                            exits == nullptr ? nullptr : exits + i * max_hits);
    }
    return SPHRAY_OK;
  });
}

int sphray_count_hits(const sphray_scene* scene, const sphray_ray* rays, size_t* counts,
                      size_t count) {
  constexpr const char* kFunction = "sphray_count_hits";
  if (int status = check_query(scene, rays, counts, count, kFunction); status != SPHRAY_OK)
    return status;
  return guarded(kFunction, [&] {
    const Scene& s = *scene->scene;
    for (std::size_t i = 0; i < count; ++i) {
      const sphray::Ray ray = to_ray(rays[i]);
      counts[i] =
          s.bvh ? sphray::count_hits(*s.bvh, ray) : sphray::count_hits(s.spheres.view(), ray);
    }
    return SPHRAY_OK;
  });
}

int sphray_nearest(const sphray_scene* scene, const float* points, float max_distance,
                   sphray_nearest_sphere* out, size_t count) {
  constexpr const char* kFunction = "sphray_nearest";
  if (int status = check_query(scene, points, out, count, kFunction); status != SPHRAY_OK)
    return status;
  return guarded(kFunction, [&] {
    const Scene& s = *scene->scene;
    for (std::size_t i = 0; i < count; ++i) {
      const sphray::Vec3 p = point_at(points, i);
      const sphray::Nearest n = s.bvh ? sphray::nearest(*s.bvh, p, max_distance)
                                      : sphray::nearest(s.spheres.view(), p, max_distance);
      out[i] = {n.id, n.distance, n.point.x, n.point.y, n.point.z};
    }
    return SPHRAY_OK;
  });
}

int sphray_inside(const sphray_scene* scene, const float* points, unsigned char* inside,
                  size_t count) {
  constexpr const char* kFunction = "sphray_inside";
  if (int status = check_query(scene, points, inside, count, kFunction); status != SPHRAY_OK)
    return status;
  return guarded(kFunction, [&] {
    const Scene& s = *scene->scene;
    for (std::size_t i = 0; i < count; ++i) {
      const sphray::Vec3 p = point_at(points, i);
      inside[i] = (s.bvh ? sphray::inside(*s.bvh, p) : sphray::inside(s.spheres.view(), p)) ? 1 : 0;
    }
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
    const Scene& s = *scene->scene;
    const sphray::Vec3 c{centre[0], centre[1], centre[2]};
    const std::span<std::uint32_t> out(ids, capacity);
    *total = s.bvh ? sphray::overlapping(*s.bvh, c, radius, out)
                   : sphray::overlapping(s.spheres.view(), c, radius, out);
    return SPHRAY_OK;
  });
}

}  // extern "C"
