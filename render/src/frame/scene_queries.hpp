// How the renderer asks the kernel about a scene's spheres: the single place that chooses the
// query structure. Above a few dozen spheres a sphray::SphereBVH answers (the same hits as brute
// force, by the kernel's contract); below, or when asked, brute force over the SphereSoA's view.
// surface() always reads the view: the tree reports the view's ids.
#pragma once

#include <optional>
#include <span>

#include "sphray/render/ray_queries.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/sphray.hpp"

namespace sphray::render {

class SceneQueries final : public RayQueries {
 public:
  /// From this many spheres on, Accel::automatic builds a BVH: about where the tree, one ray at
  /// a time, overtakes the dispatched brute force (docs/performance.md, "The BVH against
  /// Embree", its crossover).
  static constexpr std::size_t kBvhFromSpheres = 128;

  /// threads: how many the BVH builder may use, 0 for all (the tree is the same either way).
  SceneQueries(const SphereSoA& spheres, Accel accel, int threads = 0) : view_(spheres.view()) {
    bool bvh =
        accel == Accel::bvh || (accel == Accel::automatic && spheres.size() >= kBvhFromSpheres);
    if (bvh) bvh_.emplace(view_, BvhBuildOptions{static_cast<unsigned>(threads)});
  }

  bool uses_bvh() const { return bvh_.has_value(); }

  void intersect(std::span<const Ray> rays, std::span<Hit> hits) const override {
    if (bvh_) {
      sphray::intersect(*bvh_, rays, hits);
    } else {
      sphray::intersect(view_, rays, hits);
    }
  }
  // The tree's stream call takes coherent groups (shadow rays towards one light) as packets;
  // the view's, on few spheres, puts the rays across the lanes.
  void occluded(std::span<const Ray> rays, std::span<bool> blocked) const override {
    if (bvh_) {
      sphray::occluded(*bvh_, rays, blocked);
    } else {
      sphray::occluded(view_, rays, blocked);
    }
  }
  Surface surface(const Ray& ray, const Hit& hit) const { return sphray::surface(view_, ray, hit); }

 private:
  SphereView view_;
  std::optional<SphereBVH> bvh_;
};

}  // namespace sphray::render
