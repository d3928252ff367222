// The implementations a run compares, each a way to turn rays into hits on a workload's
// spheres. Adding one (the BVH, say) is a function returning more of these, appended in
// all_implementations() and all_builders() in main.cpp.
#pragma once

#include <benchmark/benchmark.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "dispatch/entry_table.hpp"  // each instruction set's entry points (sphray_kernel_internals)
#include "sphray/sphray.hpp"
#include "workload.hpp"

namespace sphray::bench {

using detail::EntryTable;
using detail::find_entries;

/// Traces rays into hits (hits.size() == rays.size()).
using Trace = std::function<void(std::span<const Ray> rays, std::span<Hit> hits)>;

struct Implementation {
  std::string name;
  int threads = 1;
  /// Brute force tests every sphere for every ray: it traces Workload::brute_rays and reports
  /// sphere tests per second; the others trace Workload::rays.
  bool brute_force = true;
  /// Spheres per SIMD batch (1 for scalar), for the cycles-per-batch counter; 0 if none.
  std::size_t width = 0;
  /// Readies the implementation for a workload outside the timed loop (building whatever it
  /// needs, or finding it already built) and returns its tracer.
  std::function<Trace(const Workload&)> prepare;
};

/// Something built from the spheres before tracing (an acceleration structure).
struct Built {
  std::shared_ptr<void> owner;  // keeps it alive; released outside the timed region
  std::size_t bytes = 0;  // memory it allocates (any copy of the spheres included), 0 if unknown
};

struct Builder {
  std::string name;
  int threads = 1;
  /// Does the untimed part for these spheres (for a refit: the first build) and returns the
  /// step that is timed.
  std::function<std::function<Built()>(const SphereSoA& spheres)> prepare;
};

/// The scalar reference, each instruction set's kernel per ray, as a stream and with the rays
/// across its lanes, the dispatched query per ray, and the dispatched stream on one and on all
/// threads.
std::vector<Implementation> kernel_implementations();

/// Traces shadow rays into blocked flags (blocked[i] for rays[i]).
using Occlusion = std::function<void(std::span<const Ray> rays, bool* blocked)>;

/// A way to answer occlusion queries on a workload's spheres (the shadow-ray benchmarks).
struct Occluder {
  std::string name;
  std::function<Occlusion(const Workload&)> prepare;
};

#if SPHRAY_BENCH_EMBREE
/// Intel Embree 3: rtcIntersect1 on one and all threads, rtcIntersect8 and rtcIntersect16
/// packets where the build has them.
std::vector<Implementation> embree_implementations();
/// rtcOccluded1, rtcOccluded8 and rtcOccluded16 (where the build has them), single thread.
std::vector<Occluder> embree_occluders();
std::vector<Builder> embree_builders();

/// Embree 3's way to every crossing along a ray (its multi-hit filter tutorials): the spheres
/// (RTC_GEOMETRY_TYPE_SPHERE_POINT) carry an intersection filter that records each hit
/// rtcIntersect1 offers and rejects it, so the traversal goes on to the ray's tfar. Embree
/// offers both roots of a sphere, near then far, each where it lies in [tnear, tfar] (closed,
/// where sphray's interval is open): the crossings of sphray's intersect_all, in traversal
/// order, which the filter sorts.
class EmbreeCrossings {
 public:
  /// A scene of its own (single-threaded build): the filter belongs to the geometry. With
  /// counting the filter counts and keeps nothing.
  EmbreeCrossings(const SphereSoA& spheres, bool counting);
  /// How many crossings in all; the nearest out.size() of them in out, sorted by t then id
  /// (nothing written when counting).
  std::size_t intersect_all(const Ray& ray, std::span<Hit> out) const;

 private:
  std::shared_ptr<void> scene_;  // an RTCScene
};
#endif

/// Double against float, each instruction set's brute force per ray (double_benchmarks.cpp).
void register_double_benchmarks();

/// The core clock next to the time stamp counter, and the divider's throughput (square root
/// and divide per vector width) that bounds the kernel: the inputs of docs/performance.md's
/// cycles-per-batch section.
void register_clock_benchmarks();
/// The queries beyond the closest hit against the closest hit (query_benchmarks.cpp).
void register_query_benchmarks();
/// Shadow rays towards one light: occlusion by the tree and by Embree (shadow_benchmarks.cpp).
void register_shadow_benchmarks();

/// sphray::SphereBVH: per ray, and the stream on one and all threads; its build and refit.
std::vector<Implementation> bvh_implementations();
std::vector<Builder> bvh_builders();

/// Times builder's step over spheres, each iteration alone (manual time), with the spheres,
/// threads and bytes per sphere as counters.
void time_build(benchmark::State& state, const SphereSoA& spheres, const Builder& builder);

/// Registers one benchmark per workload and implementation, and one per scene and builder,
/// grouped by scene so each workload is made once.
void register_benchmarks(const std::vector<Implementation>& implementations,
                         const std::vector<Builder>& builders);

}  // namespace sphray::bench
