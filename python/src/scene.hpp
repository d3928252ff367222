// sphray.Scene: spheres from numpy and the queries over them, numpy in and numpy out.
//
// Queries release the GIL and may run from any number of Python threads at once; refit()
// waits for the queries in flight and holds the next ones back while it swaps the spheres.
#pragma once

#include <pybind11/numpy.h>

#include <optional>
#include <shared_mutex>
#include <span>
#include <string>

#include "arrays.hpp"
#include "sphere_arrays.hpp"
#include "sphray/sphray.hpp"

namespace sphray::python {

namespace py = pybind11;

/// accel="auto" builds a SphereBVH from this many spheres on, as the renderer does and for the
/// same reason: about where the tree overtakes brute force (render/src/frame/scene_queries.hpp).
inline constexpr std::size_t kBvhFromSpheres = 128;

class Scene {
 public:
  /// accel: "auto", "bvh" or "brute" (the renderer's names, sphray::render::parse_accel).
  /// masks: None, or one uint32 per sphere (a ray sees a sphere if their masks share a bit).
  Scene(const py::handle& centers, const py::handle& radii, const std::string& accel,
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
  py::tuple nearest(const py::handle& points, float max_distance) const;
  /// Whether each point lies inside any sphere.
  py::array inside(const py::handle& points) const;
  /// The ids of the spheres overlapping the ball (centre, radius), ascending.
  py::array overlapping(const py::handle& centre, float radius) const;
  /// The same for many balls at once, in the sparse row layout: (offsets, ids), the ids of
  /// ball i in ids[offsets[i]:offsets[i + 1]], ascending.
  py::tuple overlaps(const py::handle& centers, const py::handle& radii) const;
  /// Every pair (i, j), i < j, of the scene's spheres where j overlaps the ball of sphere i
  /// (sphray::overlapping_pairs): (P, 2) uint32, by i then j.
  py::array overlapping_pairs() const;

  /// New centres and radii for the same spheres (same count); masks None keeps their masks.
  void refit(const py::handle& centers, const py::handle& radii, const py::handle& masks);

  std::size_t size() const { return spheres_.size(); }
  /// A copy of the spheres (centres and radii, not masks), for the renderer.
  sphray::SphereSoA copy_spheres() const;
  bool uses_bvh() const { return bvh_.has_value(); }
  /// Read-only views of the arrays the scene reads (the caller's own, or its copies).
  py::array centers() const { return read_only_view(spheres_.centers()); }
  py::array radii() const { return read_only_view(spheres_.radii()); }

 private:
  // query(tree) when the scene has one, else query(view): the one place a method chooses.
  template <class Query>
  decltype(auto) answer(Query&& query) const {
    return bvh_ ? query(*bvh_) : query(spheres_.view());
  }
  // Shared by queries, exclusive for refit. Never waited on while holding the GIL.
  mutable std::shared_mutex mutex_;
  SphereArrays spheres_;
  std::optional<SphereBVH> bvh_;

  // intersect_all and intersect_nearest: the same arrays, filled by one query or the other.
  enum class Crossings { all, nearest };
  py::tuple crossings(const py::handle& origins, const py::handle& directions, std::size_t max_hits,
                      const py::handle& tmin, const py::handle& tmax, const py::handle& mask,
                      Crossings which) const;
  // hits[i] for rays[i], through the BVH or brute force. Needs the reader lock.
  void trace(std::span<const Ray> rays, std::span<Hit> hits) const;
  // keep(i, surface) for the hit surface of each row i (rows as surface() takes them), on all
  // cores with the GIL released and the reader lock held: surface() and spawn() differ only in
  // what they keep of it. Defined in scene.cpp, its only user.
  template <class Keep>
  void each_surface(const Vec3Rows& o, const Vec3Rows& d, const FloatPerRow& t,
                    const std::vector<std::uint32_t>& ids, const Keep& keep) const;
};

}  // namespace sphray::python
