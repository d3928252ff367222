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

#include "c_api/batch_call.hpp"
#include "c_api/checks.hpp"
#include "c_api/convert.hpp"
#include "c_api/last_error.hpp"
#include "c_api/parallel_chunks.hpp"
#include "c_api/scene_handle.hpp"

namespace sphray::c_api {
namespace {

// Up to this many crossings per ray go through a buffer on the stack; more, through one on the
// heap, made once per call for all its threads.
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

// Buffers for one ray's crossings in the C++ types, per worker thread: on the stack up to
// kStackSlots, beyond that the worker's share of one heap buffer made before the threads start.
class SlotBuffers {
 public:
  SlotBuffers(std::size_t max_hits, unsigned workers) : max_hits_(max_hits) {
    if (max_hits <= kStackSlots) return;
    heap_slots_.resize(max_hits * workers);
    heap_flags_ = std::make_unique<bool[]>(max_hits * workers);
  }

  // Runs use(slots, flags) with the worker's buffers.
  template <class Use>
  void with(unsigned worker, Use&& use) {
    if (max_hits_ <= kStackSlots) {
      std::array<sphray::Hit, kStackSlots> slots;
      std::array<bool, kStackSlots> flags;
      use(std::span<sphray::Hit>(slots.data(), max_hits_),
          std::span<bool>(flags.data(), max_hits_));
      return;
    }
    const std::size_t first = worker * max_hits_;
    use(std::span<sphray::Hit>(heap_slots_.data() + first, max_hits_),
        std::span<bool>(heap_flags_.get() + first, max_hits_));
  }

 private:
  std::size_t max_hits_;
  std::vector<sphray::Hit> heap_slots_;
  std::unique_ptr<bool[]> heap_flags_;
};

int intersect_all(const sphray_scene* scene, Crossings which, const sphray_ray* rays, size_t count,
                  size_t max_hits, sphray_hit* hits, unsigned char* exits, size_t* counts,
                  const sphray_query_args* args, const char* function) {
  QueryOptions options;
  int status = check_batch(scene, rays, counts, count, args, Inputs::rays, function, options);
  if (status != SPHRAY_OK || count == 0) return status;
  if (max_hits > 0) {
    if (status = check_pointer(hits, function, "hits is NULL"); status != SPHRAY_OK) return status;
    if (max_hits > kMaxElements / count)
      return fail(SPHRAY_ERROR_TOO_LARGE, function, "count * max_hits exceeds the address space");
  }
  const unsigned workers = parallel_threads(count, options.threads);
  return guarded(function, [&] {
    SlotBuffers buffers(max_hits, workers);
    parallel_chunks(count, workers, [&](unsigned worker, std::size_t begin, std::size_t end) {
      buffers.with(worker, [&](std::span<sphray::Hit> slots, std::span<bool> flags) {
        for (std::size_t i = begin; i < end; ++i) {
          counts[i] = crossings(*scene->scene, which, to_ray(rays, options.masks, i), slots, flags,
                                hits == nullptr ? nullptr : hits + i * max_hits,
                                exits == nullptr ? nullptr : exits + i * max_hits);
        }
      });
    });
    return SPHRAY_OK;
  });
}

}  // namespace
}  // namespace sphray::c_api

using namespace sphray::c_api;

extern "C" {

int sphray_intersect_all(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                         size_t max_hits, sphray_hit* hits, unsigned char* exits, size_t* counts,
                         const sphray_query_args* args) {
  return intersect_all(scene, Crossings::all, rays, count, max_hits, hits, exits, counts, args,
                       "sphray_intersect_all");
}

int sphray_intersect_nearest(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                             size_t max_hits, sphray_hit* hits, unsigned char* exits,
                             size_t* counts, const sphray_query_args* args) {
  return intersect_all(scene, Crossings::nearest, rays, count, max_hits, hits, exits, counts, args,
                       "sphray_intersect_nearest");
}

int sphray_count_hits(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                      size_t* counts, const sphray_query_args* args) {
  constexpr const char* kFunction = "sphray_count_hits";
  QueryOptions options;
  const int status =
      check_batch(scene, rays, counts, count, args, Inputs::rays, kFunction, options);
  if (status != SPHRAY_OK || count == 0) return status;
  return run_batch(kFunction, count, options, [&](unsigned, std::size_t begin, std::size_t end) {
    scene->scene->answer([&](const auto& spheres) {
      for (std::size_t i = begin; i < end; ++i)
        counts[i] = sphray::count_hits(spheres, to_ray(rays, options.masks, i));
    });
  });
}

int sphray_nearest(const sphray_scene* scene, const float* points, size_t count, float max_distance,
                   sphray_nearest_sphere* out, const sphray_query_args* args) {
  constexpr const char* kFunction = "sphray_nearest";
  QueryOptions options;
  const int status =
      check_batch(scene, points, out, count, args, Inputs::points, kFunction, options);
  if (status != SPHRAY_OK || count == 0) return status;
  return run_batch(kFunction, count, options, [&](unsigned, std::size_t begin, std::size_t end) {
    scene->scene->answer([&](const auto& spheres) {
      for (std::size_t i = begin; i < end; ++i) {
        const sphray::Nearest n = sphray::nearest(spheres, point_at(points, i), max_distance);
        out[i] = {n.id, n.distance, n.point.x, n.point.y, n.point.z};
      }
    });
  });
}

int sphray_inside(const sphray_scene* scene, const float* points, size_t count,
                  unsigned char* inside, const sphray_query_args* args) {
  constexpr const char* kFunction = "sphray_inside";
  QueryOptions options;
  const int status =
      check_batch(scene, points, inside, count, args, Inputs::points, kFunction, options);
  if (status != SPHRAY_OK || count == 0) return status;
  return run_batch(kFunction, count, options, [&](unsigned, std::size_t begin, std::size_t end) {
    scene->scene->answer([&](const auto& spheres) {
      for (std::size_t i = begin; i < end; ++i)
        inside[i] = sphray::inside(spheres, point_at(points, i)) ? 1 : 0;
    });
  });
}

int sphray_overlapping(const sphray_scene* scene, const float* centre, float radius,
                       size_t capacity, uint32_t* ids, size_t* total) {
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
