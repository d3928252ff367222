// Incoherent rays through a scene, the one recipe of `sphray bench` (bench_rays.cpp) and of the
// benchmark program (bench/workload.cpp): origins uniform in the box of the scene's spheres,
// directions uniform on the unit sphere, from a fixed seed.
#pragma once

#include <cstddef>
#include <vector>

#include "sphray/sphray.hpp"

namespace sphray::render::bench {

struct Box {
  Vec3 lo, hi;
};

/// The bounds of the spheres, leaving out those over 10 times the median radius (a ground
/// sphere of radius 1000 under spheres of radius 1 would otherwise put nearly every origin far
/// from anything); the box [-1, 1]^3 when no sphere is left.
Box sphere_box(const SphereSoA& spheres);

/// count rays with origins uniform in box, directions uniform on the unit sphere, and tmin.
std::vector<Ray> random_rays(const Box& box, std::size_t count, unsigned seed, float tmin);

}  // namespace sphray::render::bench
