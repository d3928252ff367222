// Double precision: a 1 mm sphere resting on a 10 km ground sphere, 100 km from the origin,
// where float's spacing is 8 mm (docs/double.md). A tree over the doubles finds it where exact
// arithmetic puts it.
#include <cmath>
#include <cstdio>

#include <sphray/sphray.hpp>

int main() {
  const sphray::Vec3d centre{1e5, 0.0, 0.0};
  sphray::SphereSoAd spheres;
  spheres.add(centre, 1e-3);                                       // id 0: 1 mm
  spheres.add(centre - sphray::Vec3d{0.0, 1e4 + 1e-3, 0.0}, 1e4);  // id 1: the ground below it
  const sphray::SphereBVHd tree(spheres.view());

  // From 1 m away, level with the sphere's centre: it enters the sphere at t = 1 - 1e-3.
  const sphray::Rayd ray{centre - sphray::Vec3d{1.0, 0.0, 0.0}, {1.0, 0.0, 0.0}};
  const sphray::Hitd hit = sphray::intersect(tree, ray);
  if (!hit.found()) {
    std::printf("missed the millimetre sphere\n");
    return 1;
  }
  const sphray::Surfaced s = sphray::surface(spheres.view(), ray, hit);
  std::printf("sphere %u at t = %.12f, point (%.9f, %.9f, %.9f)\n", hit.id, hit.t, s.point.x,
              s.point.y, s.point.z);
  return hit.id == 0 && std::fabs(hit.t - (1.0 - 1e-3)) < 1e-9 ? 0 : 1;
}
