// sphray_intersect_all, sphray_intersect_nearest, sphray_count_hits, sphray_nearest,
// sphray_inside, sphray_overlapping, and their _d forms:
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
template <Scalar S>
std::size_t crossings(const BasicScene<S>& scene, Crossings which, const BasicRay<S>& ray,
                      std::span<BasicHit<S>> slots, std::span<bool> flags, CHit<S>* hits,
                      unsigned char* exits) {
  const std::size_t total = scene.answer([&](const auto& spheres) {
    return which == Crossings::all ? sphray::intersect_all(spheres, ray, slots, flags)
                                   : sphray::intersect_nearest(spheres, ray, slots, flags);
  });
  for (std::size_t k = 0; k < std::min(slots.size(), total); ++k) {
    hits[k] = to_c(slots[k]);
    if (exits != nullptr) exits[k] = flags[k] ? 1 : 0;
  }
  return total;
}

// Buffers for one ray's crossings in the C++ types, per worker thread: on the stack up to
// kStackSlots, beyond that the worker's share of one heap buffer made before the threads start.
template <Scalar S>
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
      std::array<BasicHit<S>, kStackSlots> slots;
      std::array<bool, kStackSlots> flags;
      use(std::span<BasicHit<S>>(slots.data(), max_hits_),
          std::span<bool>(flags.data(), max_hits_));
      return;
    }
    const std::size_t first = worker * max_hits_;
    use(std::span<BasicHit<S>>(heap_slots_.data() + first, max_hits_),
        std::span<bool>(heap_flags_.get() + first, max_hits_));
  }

 private:
  std::size_t max_hits_;
  std::vector<BasicHit<S>> heap_slots_;
  std::unique_ptr<bool[]> heap_flags_;
};

// sphray_intersect_all, _intersect_nearest and their _d forms.
template <Scalar S>
int intersect_all(const sphray_scene* scene, Crossings which, const CRay<S>* rays, size_t count,
                  size_t max_hits, CHit<S>* hits, unsigned char* exits, size_t* counts,
                  const sphray_query_args* args, const char* function) {
  QueryOptions options;
  int status = check_batch<S>(scene, rays, counts, count, args, Inputs::rays, function, options);
  if (status != SPHRAY_OK || count == 0) return status;
  if (max_hits > 0) {
    if (status = check_pointer(hits, function, "hits is NULL"); status != SPHRAY_OK) return status;
    if (max_hits > kMaxElements<S> / count)
      return fail(SPHRAY_ERROR_TOO_LARGE, function, "count * max_hits exceeds the address space");
  }
  const unsigned workers = parallel_threads(count, options.threads);
  const BasicScene<S>& in = *scene->scene->in<S>();
  return guarded(function, [&] {
    SlotBuffers<S> buffers(max_hits, workers);
    parallel_chunks(count, workers, [&](unsigned worker, std::size_t begin, std::size_t end) {
      buffers.with(worker, [&](std::span<BasicHit<S>> slots, std::span<bool> flags) {
        for (std::size_t i = begin; i < end; ++i) {
          counts[i] = crossings(in, which, to_ray(rays, options.masks, i), slots, flags,
                                hits == nullptr ? nullptr : hits + i * max_hits,
                                exits == nullptr ? nullptr : exits + i * max_hits);
        }
      });
    });
    return SPHRAY_OK;
  });
}

// sphray_count_hits and _count_hits_d.
template <Scalar S>
int count_hits(const sphray_scene* scene, const CRay<S>* rays, size_t count, size_t* counts,
               const sphray_query_args* args, const char* function) {
  QueryOptions options;
  const int status =
      check_batch<S>(scene, rays, counts, count, args, Inputs::rays, function, options);
  if (status != SPHRAY_OK || count == 0) return status;
  return run_batch(function, count, options, [&](unsigned, std::size_t begin, std::size_t end) {
    scene->scene->in<S>()->answer([&](const auto& spheres) {
      for (std::size_t i = begin; i < end; ++i)
        counts[i] = sphray::count_hits(spheres, to_ray(rays, options.masks, i));
    });
  });
}

// sphray_nearest and _nearest_d.
template <Scalar S, class Out>
int nearest_spheres(const sphray_scene* scene, const S* points, size_t count, S max_distance,
                    Out* out, const sphray_query_args* args, const char* function) {
  QueryOptions options;
  const int status =
      check_batch<S>(scene, points, out, count, args, Inputs::points, function, options);
  if (status != SPHRAY_OK || count == 0) return status;
  return run_batch(function, count, options, [&](unsigned, std::size_t begin, std::size_t end) {
    scene->scene->in<S>()->answer([&](const auto& spheres) {
      for (std::size_t i = begin; i < end; ++i) {
        const BasicNearest<S> n = sphray::nearest(spheres, point_at(points, i), max_distance);
        out[i] = {n.id, n.distance, n.point.x, n.point.y, n.point.z};
      }
    });
  });
}

// sphray_inside and _inside_d.
template <Scalar S>
int inside_any(const sphray_scene* scene, const S* points, size_t count, unsigned char* inside,
               const sphray_query_args* args, const char* function) {
  QueryOptions options;
  const int status =
      check_batch<S>(scene, points, inside, count, args, Inputs::points, function, options);
  if (status != SPHRAY_OK || count == 0) return status;
  return run_batch(function, count, options, [&](unsigned, std::size_t begin, std::size_t end) {
    scene->scene->in<S>()->answer([&](const auto& spheres) {
      for (std::size_t i = begin; i < end; ++i)
        inside[i] = sphray::inside(spheres, point_at(points, i)) ? 1 : 0;
    });
  });
}

// sphray_overlapping and _overlapping_d.
template <Scalar S>
int overlapping_ball(const sphray_scene* scene, const S* centre, S radius, size_t capacity,
                     uint32_t* ids, size_t* total, const char* function) {
  int status = check_scene_in<S>(scene, function);
  if (status == SPHRAY_OK) status = check_pointer(centre, function, "centre is NULL");
  if (status == SPHRAY_OK) status = check_pointer(total, function, "total is NULL");
  if (status == SPHRAY_OK && capacity > 0) status = check_pointer(ids, function, "ids is NULL");
  if (status == SPHRAY_OK && capacity > kMaxElements<>)
    status = fail(SPHRAY_ERROR_TOO_LARGE, function, "capacity exceeds the address space");
  if (status != SPHRAY_OK) return status;
  return guarded(function, [&] {
    const BasicVec3<S> c{centre[0], centre[1], centre[2]};
    const std::span<std::uint32_t> out(ids, capacity);
    *total = scene->scene->in<S>()->answer(
        [&](const auto& spheres) { return sphray::overlapping(spheres, c, radius, out); });
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
  return intersect_all<float>(scene, Crossings::all, rays, count, max_hits, hits, exits, counts,
                              args, "sphray_intersect_all");
}

int sphray_intersect_all_d(const sphray_scene* scene, const sphray_ray_d* rays, size_t count,
                           size_t max_hits, sphray_hit_d* hits, unsigned char* exits,
                           size_t* counts, const sphray_query_args* args) {
  return intersect_all<double>(scene, Crossings::all, rays, count, max_hits, hits, exits, counts,
                               args, "sphray_intersect_all_d");
}

int sphray_intersect_nearest(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                             size_t max_hits, sphray_hit* hits, unsigned char* exits,
                             size_t* counts, const sphray_query_args* args) {
  return intersect_all<float>(scene, Crossings::nearest, rays, count, max_hits, hits, exits, counts,
                              args, "sphray_intersect_nearest");
}

int sphray_intersect_nearest_d(const sphray_scene* scene, const sphray_ray_d* rays, size_t count,
                               size_t max_hits, sphray_hit_d* hits, unsigned char* exits,
                               size_t* counts, const sphray_query_args* args) {
  return intersect_all<double>(scene, Crossings::nearest, rays, count, max_hits, hits, exits,
                               counts, args, "sphray_intersect_nearest_d");
}

int sphray_count_hits(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                      size_t* counts, const sphray_query_args* args) {
  return count_hits<float>(scene, rays, count, counts, args, "sphray_count_hits");
}

int sphray_count_hits_d(const sphray_scene* scene, const sphray_ray_d* rays, size_t count,
                        size_t* counts, const sphray_query_args* args) {
  return count_hits<double>(scene, rays, count, counts, args, "sphray_count_hits_d");
}

int sphray_nearest(const sphray_scene* scene, const float* points, size_t count, float max_distance,
                   sphray_nearest_sphere* out, const sphray_query_args* args) {
  return nearest_spheres(scene, points, count, max_distance, out, args, "sphray_nearest");
}

int sphray_nearest_d(const sphray_scene* scene, const double* points, size_t count,
                     double max_distance, sphray_nearest_sphere_d* out,
                     const sphray_query_args* args) {
  return nearest_spheres(scene, points, count, max_distance, out, args, "sphray_nearest_d");
}

int sphray_inside(const sphray_scene* scene, const float* points, size_t count,
                  unsigned char* inside, const sphray_query_args* args) {
  return inside_any(scene, points, count, inside, args, "sphray_inside");
}

int sphray_inside_d(const sphray_scene* scene, const double* points, size_t count,
                    unsigned char* inside, const sphray_query_args* args) {
  return inside_any(scene, points, count, inside, args, "sphray_inside_d");
}

int sphray_overlapping(const sphray_scene* scene, const float* centre, float radius,
                       size_t capacity, uint32_t* ids, size_t* total) {
  return overlapping_ball(scene, centre, radius, capacity, ids, total, "sphray_overlapping");
}

int sphray_overlapping_d(const sphray_scene* scene, const double* centre, double radius,
                         size_t capacity, uint32_t* ids, size_t* total) {
  return overlapping_ball(scene, centre, radius, capacity, ids, total, "sphray_overlapping_d");
}

}  // extern "C"
