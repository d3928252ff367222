// How the renderer asks the kernel about a scene's spheres: the single place that chooses the
// query structure. Today that is brute force over the SphereSoA's view; when the kernel offers
// sphray::SphereBVH, build it in the constructor (for scenes above a few hundred spheres) and
// route the three calls below through it. Nothing else in render/ needs to change.
#pragma once

#include <span>

#include "sphray/sphray.hpp"

namespace sphray::render {

class SceneQueries {
 public:
  explicit SceneQueries(const SphereSoA& spheres) : view_(spheres.view()) {}

  void intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
    sphray::intersect(view_, rays, hits);
  }
  bool occluded(const Ray& ray) const { return sphray::occluded(view_, ray); }
  Surface surface(const Ray& ray, const Hit& hit) const { return sphray::surface(view_, ray, hit); }

 private:
  SphereView view_;
};

}  // namespace sphray::render
