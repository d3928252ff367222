// What every benchmark runs on: a scene from the renderer's presets and a ray set, made once
// outside the timed loops, with the scalar reference's hits on a sample of the rays.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "bench/random_rays.hpp"
#include "sphray/sphray.hpp"

namespace sphray::bench {

/// coherent: a pinhole camera's rays; incoherent: random origins and directions; bounce: the
/// rays path mode traces after the camera's (bounces 1 to 3, depth 2 to 4 counting the camera
/// ray as 1), recorded from a 512 x 512 frame, each starting on a sphere at sphray::spawn().
enum class RayKind { coherent, incoherent, bounce };

std::string_view ray_kind_name(RayKind kind);

/// The kinds a scene is run with: coherent and incoherent everywhere, bounce rays on the
/// scenes of a path-traced frame's workload (rtiow-final and random:65536).
std::span<const RayKind> ray_kinds(std::string_view scene);

/// The scenes of every run, smallest first: the renderer's presets and its random scenes.
std::span<const std::string_view> scene_names();

/// Rays in a full set: the 512 x 512 camera image for coherent rays, as many random ones.
inline constexpr std::size_t kFullRays = 512 * 512;
/// Brute force tests at most this many ray/sphere pairs per pass over its rays (and never
/// fewer than kMinBruteRays rays), so one pass on a million spheres takes a fraction of a
/// second rather than minutes. Rays per second stays the unit.
inline constexpr std::size_t kBruteTestBudget = std::size_t{1} << 26;
inline constexpr std::size_t kMinBruteRays = 256;
/// Rays whose hits every implementation must reproduce before it is timed.
inline constexpr std::size_t kSampleRays = 1024;

using render::bench::Box;

struct Workload {
  std::string scene;
  RayKind kind;
  SphereSoA spheres;
  /// The full set, for the implementations whose cost does not grow with the sphere count.
  std::vector<Ray> rays;
  /// The same kind of rays, fewer on large scenes, for the brute force implementations.
  std::vector<Ray> brute_rays;
  /// Rays drawn from brute_rays, and the scalar reference's hits on them.
  std::vector<Ray> sample;
  std::vector<Hit> expected;

  SphereView view() const { return spheres.view(); }
};

/// The workload for a scene and ray kind, made on first use and kept until another one is
/// asked for (benchmarks run grouped by workload, and a million-sphere one is large).
const Workload& workload(std::string_view scene, RayKind kind);

/// How many rays brute force traces on a scene of this many spheres: a power of 4 (a square
/// camera image) between kMinBruteRays and kFullRays.
std::size_t brute_ray_count(std::size_t spheres);

// Random rays: the recipe `sphray bench` uses (render/src/bench/random_rays.hpp), with tmin 0 here.
using render::bench::random_rays;
using render::bench::sphere_box;

}  // namespace sphray::bench
