// Before an implementation is timed, its answers are compared with the scalar reference's (or,
// for another library, with sphray's), so that a fast wrong answer is never reported as a
// result: the benchmark programs (bench/) and `sphray bench --query every-hit` share these
// rules.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "sphray/sphray.hpp"

namespace sphray::render::bench {

/// t may differ from the reference by this fraction of max(1, |t|): float rounding in a
/// different order (FMA, SIMD lanes, Embree's own formulation), never a different surface.
inline constexpr float kRelativeTolerance = 1e-3f;

struct Agreement {
  std::size_t compared = 0;
  std::size_t id_ties = 0;  // same t within tolerance, different sphere: a tie decided by rounding
  std::size_t undecided = 0;    // rays float cannot decide (compare_crossings), not compared
  std::string first_mismatch;   // empty when every hit agrees
  std::size_t mismatch_at = 0;  // the index of the ray it describes

  bool ok() const { return first_mismatch.empty(); }
};

/// Compares got with expected ray by ray: both miss, or both hit the same sphere at t within
/// the tolerance (or two spheres at the same t within it, counted as a tie).
Agreement compare_hits(std::span<const Ray> rays, std::span<const Hit> expected,
                       std::span<const Hit> got);

/// One ray's crossings: how many in all, and the nearest ones (up to the room given) sorted by
/// t then id, or none kept when only the count is asked for.
struct Crossings {
  std::size_t total = 0;
  std::vector<Hit> nearest;
};

/// Compares got with expected ray by ray where float decides them: the same total, and at
/// each place of the kept lists a t within the tolerance and the same sphere, or another
/// sphere at that t within the tolerance (a tie, counted). A ray on which either side has a
/// sphere's two roots within the tolerance of each other (it grazes the sphere: rounding
/// decides whether it crosses at all) is left out when the totals differ, and counted in
/// `undecided`.
Agreement compare_crossings(std::span<const Crossings> expected, std::span<const Crossings> got);

}  // namespace sphray::render::bench
