// How the renderer asks the kernel about a scene's spheres: the single place that chooses the
// query structure. Above a few dozen spheres a sphray::SphereBVH answers (the same hits as brute
// force, by the kernel's contract); below, or when asked, brute force over the spheres' view.
// surface() always reads the view: the tree reports the view's ids.
#pragma once

#include <optional>
#include <span>
#include <stdexcept>

#include "sphray/render/ray_queries.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/sphray.hpp"

namespace sphray::render {

/// Refuses, with std::invalid_argument, a share of the tiles with collective queries that need
/// every process to make the same calls: processes with shares of other sizes would not (and in
/// path mode, a tile's rounds depend on its paths).
inline void check_share(const RayQueries& queries, const RenderOptions& options) {
  if (queries.collective() && options.share.count > 1 && !queries.uneven_calls()) {
    throw std::invalid_argument(
        "tile share: queries shared between processes render the whole image on every "
        "process, unless they take uneven calls (routed)");
  }
}

/// The choice, in either precision: a tree or brute force over view.
template <Scalar S>
class SphereQueries {
 public:
  /// From this many spheres on, Accel::automatic builds a BVH: about where the tree, one ray at
  /// a time, overtakes the dispatched brute force (docs/performance.md, "The BVH against
  /// Embree", its crossover).
  static constexpr std::size_t kBvhFromSpheres = 128;

  /// threads: how many the BVH builder may use, 0 for all (the tree is the same either way).
  SphereQueries(BasicSphereView<S> view, Accel accel, int threads = 0) : view_(view) {
    bool bvh = accel == Accel::bvh || (accel == Accel::automatic && view.count >= kBvhFromSpheres);
    if (bvh) bvh_.emplace(view_, BvhBuildOptions{static_cast<unsigned>(threads)});
  }

  bool uses_bvh() const { return bvh_.has_value(); }

  void intersect(std::span<const BasicRay<S>> rays, std::span<BasicHit<S>> hits) const {
    if (bvh_) {
      sphray::intersect(*bvh_, rays, hits);
    } else {
      sphray::intersect(view_, rays, hits);
    }
  }
  // The tree's stream call takes coherent groups (shadow rays towards one light) as packets;
  // the view's, on few spheres, puts the rays across the lanes.
  void occluded(std::span<const BasicRay<S>> rays, std::span<bool> blocked) const {
    if (bvh_) {
      sphray::occluded(*bvh_, rays, blocked);
    } else {
      sphray::occluded(view_, rays, blocked);
    }
  }
  BasicSurface<S> surface(const BasicRay<S>& ray, const BasicHit<S>& hit) const {
    return sphray::surface(view_, ray, hit);
  }

 private:
  BasicSphereView<S> view_;
  std::optional<BasicSphereBVH<S>> bvh_;
};

/// The float choice as the RayQueries the renderer's float loops take.
class SceneQueries final : public RayQueries {
 public:
  static constexpr std::size_t kBvhFromSpheres = SphereQueries<float>::kBvhFromSpheres;

  SceneQueries(const SphereSoA& spheres, Accel accel, int threads = 0)
      : queries_(spheres.view(), accel, threads) {}

  bool uses_bvh() const { return queries_.uses_bvh(); }

  void intersect(std::span<const Ray> rays, std::span<Hit> hits) const override {
    queries_.intersect(rays, hits);
  }
  void occluded(std::span<const Ray> rays, std::span<bool> blocked) const override {
    queries_.occluded(rays, blocked);
  }
  Surface surface(const Ray& ray, const Hit& hit) const { return queries_.surface(ray, hit); }

 private:
  SphereQueries<float> queries_;
};

}  // namespace sphray::render
