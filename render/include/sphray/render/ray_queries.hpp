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
  /// same on all). It traces the tiles of its share in groups of 64, each group one call a
  /// sample (and one for the shadow rays), or in path mode one call a bounce, the paths of all
  /// the group's tiles together; the batches differ between processes (each its own tiles'
  /// rays). With a share of the tiles, processes make different numbers of calls: the renderer
  /// refuses it unless uneven_calls().
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
