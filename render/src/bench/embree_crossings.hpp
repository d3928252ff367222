// Every crossing of a ray with Embree 3, the way its multi-hit tutorials find them: the spheres
// carry an intersection filter that sees each hit the traversal finds, in traversal order,
// records it and rejects it (valid = 0), so that the ray's tfar never shrinks and the walk goes
// on to the end of the segment. The per-ray state travels in the intersect context, extended as
// the tutorials extend it. Embree offers a sphere's near root, then its far root, each where it
// lies in [tnear, tfar]: sphray's intersect_all's crossings (docs/queries.md, "Against Embree's
// filter"). For the comparisons only (`sphray bench --query every-hit`, bench/), as
// embree_spheres.hpp.
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>
#include <cstddef>
#include <span>

#include "bench/embree_spheres.hpp"
#include "sphray/sphray.hpp"

namespace sphray::embree {

struct CrossingContext {
  RTCIntersectContext context;  // first: the filter gets a pointer to it and casts back
  Hit* nearest = nullptr;       // the nearest crossings so far, sorted by t then id
  std::size_t room = 0;
  std::size_t total = 0;  // every crossing offered
};

inline CrossingContext& crossing_context(const RTCFilterFunctionNArguments* args) {
  return *reinterpret_cast<CrossingContext*>(args->context);
}

/// The filter that keeps the `room` nearest by insertion (a crossing behind a full list costs
/// one comparison), as sphray's intersect_all keeps its span, and counts them all.
inline void keep_nearest(const RTCFilterFunctionNArguments* args) {
  CrossingContext& c = crossing_context(args);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    args->valid[i] = 0;
    // Inside the filter, the ray's tfar is the distance of the hit being offered.
    const Hit hit{RTCRayN_tfar(args->ray, args->N, i), RTCHitN_primID(args->hit, args->N, i)};
    const std::size_t kept = std::min(c.total++, c.room);
    std::size_t at = kept;
    while (at > 0 && (hit.t < c.nearest[at - 1].t ||
                      (hit.t == c.nearest[at - 1].t && hit.id < c.nearest[at - 1].id)))
      --at;
    if (at == c.room) continue;
    const std::size_t end = std::min(kept, c.room - 1);
    std::copy_backward(c.nearest + at, c.nearest + end, c.nearest + end + 1);
    c.nearest[at] = hit;
  }
}

/// The filter that only counts.
inline void count_only(const RTCFilterFunctionNArguments* args) {
  CrossingContext& c = crossing_context(args);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    args->valid[i] = 0;
    ++c.total;
  }
}

/// How many crossings ray has in a scene whose spheres carry one of these filters; with
/// keep_nearest, the nearest nearest.size() of them in nearest, sorted by t then id.
inline std::size_t every_crossing(RTCScene scene, const Ray& ray, std::span<Hit> nearest) {
  CrossingContext c;
  rtcInitIntersectContext(&c.context);
  c.nearest = nearest.data();
  c.room = nearest.size();
  RTCRayHit rh = to_embree(ray);
  rtcIntersect1(scene, &c.context, &rh);
  return c.total;
}

}  // namespace sphray::embree
