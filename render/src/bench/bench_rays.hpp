// The rays `sphray bench` traces through a scene: its camera's, or random ones; and the scalar
// reference's hits on a sample of them, which every row must reproduce before it is timed.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "sphray/render/scene.hpp"
#include "sphray/sphray.hpp"

namespace sphray::render::bench {

/// camera: the scene camera's rays through the pixel centres of its image, row by row (what the
/// renderer traces first; coherent). random: origins uniform in the box of the scene's spheres
/// and directions uniform on the unit sphere, tmin 1e-3 (incoherent).
enum class RayKind { camera, random };

/// Random rays in a set.
inline constexpr std::size_t kRandomRays = std::size_t{1} << 18;
/// Brute force tests at most this many ray/sphere pairs per pass over its rays (and never
/// fewer than kMinBruteRays rays), so that a pass stays short on large scenes.
inline constexpr std::size_t kBruteTestBudget = std::size_t{1} << 24;
inline constexpr std::size_t kMinBruteRays = 256;
/// Rays every row must answer as the scalar reference does before it is timed.
inline constexpr std::size_t kSampleRays = 1024;

struct RaySet {
  RayKind kind;
  std::string description;  // "1200x675 camera image", "262144 random rays"
  std::vector<Ray> rays;
  /// Rays spread evenly over rays, fewer on large scenes, for the brute-force rows.
  std::vector<Ray> brute_rays;
  /// Rays spread evenly over brute_rays, and sphray::scalar::intersect's hits on them.
  std::vector<Ray> sample;
  std::vector<Hit> expected;
};

const char* ray_kind_name(RayKind kind);

RaySet make_ray_set(const Scene& scene, RayKind kind);

/// count rays spread evenly over rays (over the whole image, not its top rows); all of them if
/// there are no more.
std::vector<Ray> spread(const std::vector<Ray>& rays, std::size_t count);

}  // namespace sphray::render::bench
