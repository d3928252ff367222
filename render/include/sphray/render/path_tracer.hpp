// Path mode: a unidirectional path tracer in the spirit of Ray Tracing in One Weekend, built on
// the kernel's public calls alone. Per 16x16 tile and pass of up to 16 samples, the tile's paths
// advance as one wavefront of 256 lanes, the paths of later samples taking the lanes of ended
// ones: every round is a stream call (sphray::intersect over the live rays, through the BVH on
// large scenes), each hit scatters by its sphere's material, and each next ray starts at
// sphray::spawn(), never inside the sphere it leaves.
//
// Deterministic: every random number comes from (seed, pixel, sample, bounce) alone, each
// pixel's samples are summed in sample order by one thread, so the image is the same bit for
// bit whatever the thread count.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {

/// The mean radiance of every pixel (linear, not clamped), rows top to bottom: what path mode
/// encodes (gamma 2) into its image. options.mode is ignored. Throws as render() does, and
/// std::invalid_argument for a max_depth or time_limit out of range.
std::vector<Vec3> render_radiance(const Scene& scene, const RenderOptions& options,
                                  const Progress& progress = {}, RenderStats* stats = nullptr);

/// The same, the hits answered by queries (render() with a RayQueries).
std::vector<Vec3> render_radiance(const Scene& scene, const RayQueries& queries,
                                  const RenderOptions& options, const Progress& progress = {},
                                  RenderStats* stats = nullptr);

/// render() in Mode::path: render_radiance, gamma 2, bytes as the book writes them.
Image render_path(const Scene& scene, const RenderOptions& options, const Progress& progress,
                  RenderStats* stats);
Image render_path(const Scene& scene, const RayQueries& queries, const RenderOptions& options,
                  const Progress& progress, RenderStats* stats);

/// Every ray path mode traces at bounce first_bounce to last_bounce (0: the camera rays,
/// 1: the first bounce), in tile and sample order, on one thread: the benchmark's recorded
/// workload. options as for render_radiance (time_limit ignored).
std::vector<Ray> record_path_rays(const Scene& scene, const RenderOptions& options,
                                  int first_bounce, int last_bounce);

}  // namespace sphray::render
