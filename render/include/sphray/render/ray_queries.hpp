// RayQueries: what the renderer asks of a scene's spheres, one batch of rays at a time. The
// renderer makes its own from the scene (a BVH, or brute force below a few dozen spheres); a
// caller may pass another that gives the same answers, such as spheres spread over the
// processes of an MPI job (mpi/). Surfaces are always read from the scene's own spheres.
#pragma once

#include <span>

#include "sphray/sphray.hpp"

namespace sphray::render {

class RayQueries {
 public:
  virtual ~RayQueries() = default;
  /// hits[i]: the closest hit of rays[i] among the scene's spheres, with the scene's ids.
  virtual void intersect(std::span<const Ray> rays, std::span<Hit> hits) const = 0;
  /// out[i]: whether rays[i] hits any of the scene's spheres in (tmin, tmax).
  virtual void occluded(std::span<const Ray> rays, std::span<bool> out) const = 0;
  /// True when every call is collective: made by every process, in the same order. The
  /// renderer then traces on the calling thread and refuses a time limit (a clock is not the
  /// same on all). Outside path mode it traces all the tiles of its share together, one call a
  /// sample (and one for the shadow rays), so that every process makes the same calls whatever
  /// its share: the batches may differ between processes (each its own tiles' rays). Path mode
  /// traces a group of tiles together, one call a bounce, and the number of bounces depends on
  /// the paths: with a share of the tiles, it needs uneven_calls().
  virtual bool collective() const { return false; }
  /// Collective queries only: true when the processes may make different numbers of calls,
  /// each ending its own with finish(). The renderer calls finish() once at the end of every
  /// frame it traces with collective queries.
  virtual bool uneven_calls() const { return false; }
  /// With uneven_calls(): takes part in the other processes' calls until every process has
  /// called finish().
  virtual void finish() const {}
};

}  // namespace sphray::render
