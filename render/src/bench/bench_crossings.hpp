// The rows `sphray bench --query every-hit` times: every crossing of a ray with the spheres, by
// sphray's default tree (count_hits, and intersect_all and intersect_nearest into 16 slots) and
// by Embree's multi-hit filters, each checked before it is timed.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "bench/bench_rays.hpp"
#include "bench/bench_timing.hpp"
#include "sphray/sphray.hpp"

namespace sphray::render::bench {

/// The crossings the listing rows keep per ray.
inline constexpr std::size_t kCrossingRoom = 16;

/// Answers the rays' every-hit query: totals[i] for rays[i] and, unless lists is empty (a
/// counting row), its nearest crossings from lists[i * kCrossingRoom] on, sorted by t then id.
/// Called on several threads at once, each with its own part of the rays.
using CrossingTrace = std::function<void(std::span<const Ray> rays, std::span<std::size_t> totals,
                                         std::span<Hit> lists)>;

struct CrossingRow {
  std::string name;  // "tree count_hits", "embree filter all16"
  /// Keeps no list: only the totals are compared.
  bool counts_only = false;
  /// The totals are how many crossings it kept, not how many there are (intersect_nearest).
  bool kept_only = false;
  /// sphray's rows must give the scalar reference's crossings on the sample; another
  /// library's must agree with sphray's default tree on every ray, up to float ties.
  bool sphray = true;
  /// For another library's row: the sphray row that gives the same answer, for the ratio.
  std::string same_answer_as = {};
  std::function<CrossingTrace(SphereView spheres)> prepare;
  std::string skipped = {};
  /// The row another library's rows are checked against, on every ray (one of sphray's).
  bool reference = false;
};

/// The default tree's count_hits, intersect_all16 and intersect_nearest16 (a tree built the
/// way sphray::SphereBVH builds one by default; the rows share it).
std::vector<CrossingRow> sphray_crossing_rows();
/// Embree 3's counting and collecting filters (embree_crossings.hpp), where this build has
/// Embree; none otherwise.
std::vector<CrossingRow> embree_crossing_rows();

/// What a row's check found: the first disagreement (empty if none), how many rays it checked,
/// how many of them float could not decide (a ray grazing a sphere, or meeting a huge one at a
/// shallow angle: where the answers differ there, rounding decides, and the ray is not held
/// against either) and how many crossings tied with another sphere's at t.
struct CrossingCheck {
  std::string mismatch;
  std::size_t rays = 0, undecided = 0, ties = 0;
};

/// Checks a sphray row on set.sample against the scalar reference's crossings (of spheres),
/// and another library's on every ray of set against reference, sphray's intersect_all16.
CrossingCheck check_crossing_row(const CrossingRow& row, const CrossingTrace& trace,
                                 const RaySet& set, SphereView spheres,
                                 const CrossingTrace& reference);

/// Times the row as time_passes does, over every ray of set.
RowTiming time_crossing_row(const CrossingRow& row, const CrossingTrace& trace, const RaySet& set,
                            int threads, double seconds, int repetitions);

}  // namespace sphray::render::bench
