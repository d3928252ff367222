// The smallest useful sphray program: a few spheres, a few rays, closest hits and a shadow test.
#include <cstdio>
#include <vector>

#include <sphray/sphray.hpp>

int main() {
  sphray::SphereSoA spheres;
  spheres.add({0.0f, 0.0f, -1.0f}, 0.5f);       // id 0: Ray Tracing in One Weekend's sphere
  spheres.add({0.0f, -100.5f, -1.0f}, 100.0f);  // id 1: the ground

  const std::vector<sphray::Ray> rays = {
      {{0, 0, 0}, {0, 0, -1}},      // straight at sphere 0: t = 0.5
      {{0, 0, 0}, {0, -1, -0.1f}},  // down to the ground
      {{0, 0, 0}, {0, 1, 0}},       // up into the sky: a miss
  };
  std::vector<sphray::Hit> hits(rays.size());
  sphray::intersect(spheres.view(), rays, hits);  // a stream of closest hits

  std::printf("sphray %s on %s\n", sphray::kVersion,
              std::string(sphray::isa_name(sphray::active_isa())).c_str());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!hits[i].found()) {
      std::printf("ray %zu: miss\n", i);
      continue;
    }
    const sphray::Surface s = sphray::surface(spheres.view(), rays[i], hits[i]);
    // A shadow ray towards a light straight above. spawn() starts it just past the hit point's
    // rounding error, so that it never meets the sphere it leaves (a fixed offset such as
    // 1e-4 * normal fails at some scale: docs/kernel.md, "Leaving a surface").
    const sphray::Ray shadow = sphray::spawn(s, {0, 1, 0});
    std::printf("ray %zu: sphere %u at t = %g, normal (%g, %g, %g), %s\n", i, hits[i].id, hits[i].t,
                s.normal.x, s.normal.y, s.normal.z,
                sphray::occluded(spheres.view(), shadow) ? "in shadow" : "lit");
  }
  const bool right = hits[0].id == 0 && hits[0].t == 0.5f && hits[1].id == 1 && !hits[2].found();
  return right ? 0 : 1;
}
