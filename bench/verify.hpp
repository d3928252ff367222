// Before an implementation is timed, its hits on a sample of the rays are compared with the
// scalar reference's, so a fast wrong answer is never reported as a result.
#pragma once

#include <span>
#include <string>

#include "sphray/sphray.hpp"

namespace sphray::bench {

/// t may differ from the reference by this fraction of max(1, |t|): float rounding in a
/// different order (FMA, SIMD lanes, Embree's own formulation), never a different surface.
inline constexpr float kRelativeTolerance = 1e-3f;

struct Agreement {
  std::size_t compared = 0;
  std::size_t id_ties = 0;  // same t within tolerance, different sphere: a tie decided by rounding
  std::string first_mismatch;  // empty when every hit agrees

  bool ok() const { return first_mismatch.empty(); }
};

/// Compares got with expected ray by ray: both miss, or both hit the same sphere at t within
/// the tolerance (or two spheres at the same t within it, counted as a tie).
Agreement compare_hits(std::span<const Ray> rays, std::span<const Hit> expected,
                       std::span<const Hit> got);

}  // namespace sphray::bench
