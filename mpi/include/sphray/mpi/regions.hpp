// Regions: the box around each rank's spheres, and the order in which a ray's segment meets
// them. Routed queries (DistributedScene::intersect_routed) send a ray only to the ranks whose
// region it crosses, front to back, so that a rank behind a nearer hit is never asked. No MPI
// here: the same order serves the ranks and a single process that plays them (a simulation).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

#include "sphray/sphray.hpp"

namespace sphray::mpi {

/// The relative slack of the region tests: 1e-5, some 170 float roundings. A region is skipped
/// only when it starts beyond the nearest hit so far, so a hit the kernel reports must never
/// lie before its region's entry: the kernel rounds t relative to the sizes of the ray's origin
/// and of the sphere's centre, and the test pads by this much of both. More slack costs
/// visits, never hits.
inline constexpr float kRegionSlack = 1e-5f;

/// An axis-aligned box, padded outward (region_box); empty when it holds no sphere that can be
/// hit.
struct RegionBox {
  float lo[3] = {0, 0, 0};
  float hi[3] = {0, 0, 0};
  bool empty = true;
};

/// The box around the spheres that can be hit (finite centre, positive finite radius), padded
/// by kRegionSlack of its largest coordinate.
RegionBox region_box(SphereView spheres);
/// The same for the spheres ids of spheres.
RegionBox region_box(SphereView spheres, std::span<const std::uint32_t> ids);

/// Where a ray's segment enters a region: the entry t, ties broken by the region's index.
/// Keys order a ray's visits; the first key lies below every real one.
struct RegionKey {
  float entry = -std::numeric_limits<float>::infinity();
  int region = -1;
};

constexpr bool operator<(const RegionKey& a, const RegionKey& b) {
  return a.entry < b.entry || (a.entry == b.entry && a.region < b.region);
}

/// The next region the ray visits after `after`: the least key above it among the regions
/// whose box the segment [ray.tmin, bound] meets (bound: ray.tmax, or the nearest hit so far;
/// widened by kRegionSlack).
/// region -1 when there is none; always -1 for an invalid ray (a NaN or infinite origin or
/// direction, a zero direction, a NaN tmin or bound), which the kernel misses anyway.
RegionKey next_region(std::span<const RegionBox> regions, const Ray& ray, float bound,
                      RegionKey after);

/// next_region's answer, and where the region after it is entered (the next key's entry after
/// it, for the same bound): infinity when none. A ray carries `then` to its next region, so
/// that once its nearest hit there is known, one comparison with reach() tells whether any
/// region is left before the hit, without another search.
struct RegionSteps {
  RegionKey next{std::numeric_limits<float>::infinity(), -1};
  float then = std::numeric_limits<float>::infinity();
};
RegionSteps next_regions(std::span<const RegionBox> regions, const Ray& ray, float bound,
                         RegionKey after);

/// How far next_region looks along the ray for a bound: the bound widened by kRegionSlack. A
/// region entered beyond it is not visited. NaN for an invalid ray.
float reach(const Ray& ray, float bound);

/// The ray a region searches when the nearest hit so far is best: bounded one float step past
/// it, since the kernel's interval is open and a sphere at the same t with a lower id must
/// still be found. The ray itself before any hit.
inline Ray bounded_by(const Ray& ray, const Hit& best) {
  Ray bounded = ray;
  if (best.found()) bounded.tmax = std::nextafter(best.t, std::numeric_limits<float>::infinity());
  return bounded;
}

/// best becomes hit (a found hit, global id) when hit is nearer: a smaller t, or the same t
/// and a lower id, the kernel's order.
inline void keep_nearer(Hit& best, const Hit& hit) {
  if (hit.t < best.t || (hit.t == best.t && hit.id < best.id)) best = hit;
}

}  // namespace sphray::mpi
