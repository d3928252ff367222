// sphray.Scene: spheres from numpy and the queries over them, numpy in and numpy out.
//
// A scene is float or double (its precision, chosen once from the arrays' dtype or by the
// caller): SceneOf<S> holds the spheres and answers every query in S, and Scene, the class
// Python sees, holds one SceneOf of either scalar and hands each call to it.
//
// Queries release the GIL and may run from any number of Python threads at once; refit()
// waits for the queries in flight and holds the next ones back while it swaps the spheres.
#pragma once

#include <pybind11/numpy.h>

#include <optional>
#include <shared_mutex>
#include <span>
#include <string>
#include <type_traits>
#include <variant>

#include "arrays.hpp"
#include "sphere_arrays.hpp"
#include "sphray/sphray.hpp"

namespace sphray::python {

namespace py = pybind11;

/// accel="auto" builds a SphereBVH from this many spheres on, as the renderer does and for the
/// same reason: about where the tree overtakes brute force (render/src/frame/scene_queries.hpp).
inline constexpr std::size_t kBvhFromSpheres = 128;

/// The spheres of one precision, S, and the queries over them: rays, points and radii read as
/// S (float32 or float64 arrays, in place when they are), results of dtype S.
template <Scalar S>
class SceneOf {
 public:
  /// "float" or "double": Scene.precision.
  static constexpr const char* kPrecision = std::is_same_v<S, float> ? "float" : "double";

  /// centers, radii: as as_real_array() returned them. accel: "auto", "bvh" or "brute" (the
  /// renderer's names, sphray::render::parse_accel). masks: None, or one uint32 per sphere (a
  /// ray sees a sphere if their masks share a bit).
  SceneOf(const py::array& centers, const py::array& radii, const std::string& accel,
          const py::handle& masks);

  /// (t, ids) of the closest hits.
  py::tuple intersect(const py::handle& origins, const py::handle& directions,
                      const py::handle& tmin, const py::handle& tmax, const py::handle& mask) const;
  /// Whether each ray hits any sphere in (tmin, tmax).
  py::array occluded(const py::handle& origins, const py::handle& directions,
                     const py::handle& tmin, const py::handle& tmax, const py::handle& mask) const;
  /// (points, normals, front_face) where each ray meets its hit.
  py::tuple surface(const py::handle& origins, const py::handle& directions, const py::handle& t,
                    const py::handle& ids) const;
  /// The origins of rays leaving each hit towards new_directions: sphray::spawn() of the hit's
  /// surface, so that they never meet that sphere again on the wrong side.
  py::array spawn(const py::handle& origins, const py::handle& directions, const py::handle& t,
                  const py::handle& ids, const py::handle& new_directions) const;
  /// Every crossing of each ray (docs/queries.md): (t, ids, exits, counts), the first max_hits
  /// crossings per ray sorted by t in (..., max_hits) arrays, unused slots t = NaN and
  /// id = NO_HIT, and each ray's total count.
  py::tuple intersect_all(const py::handle& origins, const py::handle& directions,
                          std::size_t max_hits, const py::handle& tmin, const py::handle& tmax,
                          const py::handle& mask) const;
  /// The nearest k crossings of each ray alone (sphray::intersect_nearest): intersect_all's
  /// first k, with counts how many were written rather than the total.
  py::tuple intersect_nearest(const py::handle& origins, const py::handle& directions,
                              std::size_t k, const py::handle& tmin, const py::handle& tmax,
                              const py::handle& mask) const;
  /// The number of crossings of each ray.
  py::array count_hits(const py::handle& origins, const py::handle& directions,
                       const py::handle& tmin, const py::handle& tmax,
                       const py::handle& mask) const;
  /// (ids, distances, points): the nearest sphere to each point by signed distance.
  py::tuple nearest(const py::handle& points, double max_distance) const;
  /// Whether each point lies inside any sphere.
  py::array inside(const py::handle& points) const;
  /// The ids of the spheres overlapping the ball (centre, radius), ascending.
  py::array overlapping(const py::handle& centre, double radius) const;
  /// The same for many balls at once, in the sparse row layout: (offsets, ids), the ids of
  /// ball i in ids[offsets[i]:offsets[i + 1]], ascending.
  py::tuple overlaps(const py::handle& centers, const py::handle& radii) const;
  /// Every pair (i, j), i < j, of the scene's spheres where j overlaps the ball of sphere i
  /// (sphray::overlapping_pairs): (P, 2) uint32, by i then j.
  py::array overlapping_pairs() const;

  /// New centres and radii for the same spheres (same count); masks None keeps their masks.
  void refit(const py::handle& centers, const py::handle& radii, const py::handle& masks);

  std::size_t size() const { return spheres_.size(); }
  /// A copy of the spheres (centres and radii, not masks) for the renderer, which is float
  /// only: a double scene's are rounded to the nearest float.
  sphray::SphereSoA copy_spheres() const;
  bool uses_bvh() const { return bvh_.has_value(); }
  /// Read-only views of the arrays the scene reads (the caller's own, or its copies).
  py::array centers() const { return read_only_view(spheres_.centers()); }
  py::array radii() const { return read_only_view(spheres_.radii()); }

 private:
  using Vec = BasicVec3<S>;
  using RayS = BasicRay<S>;
  using HitS = BasicHit<S>;
  using SurfaceS = BasicSurface<S>;
  using Tree = BasicSphereBVH<S>;

  // query(tree) when the scene has one, else query(view): the one place a method chooses.
  template <class Query>
  decltype(auto) answer(Query&& query) const {
    return bvh_ ? query(*bvh_) : query(spheres_.view());
  }
  // Shared by queries, exclusive for refit. Never waited on while holding the GIL.
  mutable std::shared_mutex mutex_;
  SphereArrays<S> spheres_;
  std::optional<Tree> bvh_;

  // intersect_all and intersect_nearest: the same arrays, filled by one query or the other.
  enum class Crossings { all, nearest };
  py::tuple crossings(const py::handle& origins, const py::handle& directions, std::size_t max_hits,
                      const py::handle& tmin, const py::handle& tmax, const py::handle& mask,
                      Crossings which) const;
  // hits[i] for rays[i], through the BVH or brute force. Needs the reader lock.
  void trace(std::span<const RayS> rays, std::span<HitS> hits) const;
  // keep(i, surface) for the hit surface of each row i (rows as surface() takes them), on all
  // cores with the GIL released and the reader lock held: surface() and spawn() differ only in
  // what they keep of it. Defined in scene.cpp, its only user.
  template <class Keep>
  void each_surface(const Vec3Rows<S>& o, const Vec3Rows<S>& d, const ScalarPerRow<S>& t,
                    const std::vector<std::uint32_t>& ids, const Keep& keep) const;
};

extern template class SceneOf<float>;
extern template class SceneOf<double>;

/// sphray.Scene: a SceneOf<float> or a SceneOf<double>, chosen when it is made, and every
/// method handed to the one it holds.
class Scene {
  // A SceneOf holds a mutex and cannot move: the variant is made in place, by one of the two
  // prvalues of make() (guaranteed copy elision), never moved into place.
  using Scenes = std::variant<SceneOf<float>, SceneOf<double>>;
  static Scenes make(const py::handle& centers, const py::handle& radii, const std::string& accel,
                     const py::handle& masks, const py::handle& precision);

  template <class Call>
  decltype(auto) visit(Call&& call) const {
    return std::visit(std::forward<Call>(call), scene_);
  }

  Scenes scene_;

 public:
  /// precision: None (double when centers or radii are float64, else float), "float" or
  /// "double"; anything else is a ValueError. The other arguments as SceneOf's.
  Scene(const py::handle& centers, const py::handle& radii, const std::string& accel,
        const py::handle& masks, const py::handle& precision);

  py::tuple intersect(const py::handle& origins, const py::handle& directions,
                      const py::handle& tmin, const py::handle& tmax,
                      const py::handle& mask) const {
    return visit([&](const auto& s) { return s.intersect(origins, directions, tmin, tmax, mask); });
  }
  py::array occluded(const py::handle& origins, const py::handle& directions,
                     const py::handle& tmin, const py::handle& tmax, const py::handle& mask) const {
    return visit([&](const auto& s) { return s.occluded(origins, directions, tmin, tmax, mask); });
  }
  py::tuple surface(const py::handle& origins, const py::handle& directions, const py::handle& t,
                    const py::handle& ids) const {
    return visit([&](const auto& s) { return s.surface(origins, directions, t, ids); });
  }
  py::array spawn(const py::handle& origins, const py::handle& directions, const py::handle& t,
                  const py::handle& ids, const py::handle& new_directions) const {
    return visit(
        [&](const auto& s) { return s.spawn(origins, directions, t, ids, new_directions); });
  }
  py::tuple intersect_all(const py::handle& origins, const py::handle& directions,
                          std::size_t max_hits, const py::handle& tmin, const py::handle& tmax,
                          const py::handle& mask) const {
    return visit([&](const auto& s) {
      return s.intersect_all(origins, directions, max_hits, tmin, tmax, mask);
    });
  }
  py::tuple intersect_nearest(const py::handle& origins, const py::handle& directions,
                              std::size_t k, const py::handle& tmin, const py::handle& tmax,
                              const py::handle& mask) const {
    return visit([&](const auto& s) {
      return s.intersect_nearest(origins, directions, k, tmin, tmax, mask);
    });
  }
  py::array count_hits(const py::handle& origins, const py::handle& directions,
                       const py::handle& tmin, const py::handle& tmax,
                       const py::handle& mask) const {
    return visit(
        [&](const auto& s) { return s.count_hits(origins, directions, tmin, tmax, mask); });
  }
  py::tuple nearest(const py::handle& points, double max_distance) const {
    return visit([&](const auto& s) { return s.nearest(points, max_distance); });
  }
  py::array inside(const py::handle& points) const {
    return visit([&](const auto& s) { return s.inside(points); });
  }
  py::array overlapping(const py::handle& centre, double radius) const {
    return visit([&](const auto& s) { return s.overlapping(centre, radius); });
  }
  py::tuple overlaps(const py::handle& centers, const py::handle& radii) const {
    return visit([&](const auto& s) { return s.overlaps(centers, radii); });
  }
  py::array overlapping_pairs() const {
    return visit([&](const auto& s) { return s.overlapping_pairs(); });
  }
  void refit(const py::handle& centers, const py::handle& radii, const py::handle& masks) {
    std::visit([&](auto& s) { s.refit(centers, radii, masks); }, scene_);
  }
  std::size_t size() const {
    return visit([&](const auto& s) { return s.size(); });
  }
  sphray::SphereSoA copy_spheres() const {
    return visit([&](const auto& s) { return s.copy_spheres(); });
  }
  bool uses_bvh() const {
    return visit([&](const auto& s) { return s.uses_bvh(); });
  }
  py::array centers() const {
    return visit([&](const auto& s) { return s.centers(); });
  }
  py::array radii() const {
    return visit([&](const auto& s) { return s.radii(); });
  }
  /// "float" or "double".
  std::string precision() const {
    return visit([](const auto& s) { return std::string(s.kPrecision); });
  }
};

}  // namespace sphray::python
