// DistributedScene: spheres spread over the ranks of an MPI communicator, queried as one scene.
//
// Each rank holds a share of the spheres, each with its global id, and its own SphereBVH over
// them. A query takes a batch of rays (or points) that every rank holds alike: each rank
// answers it over its own spheres, then one MPI_Allreduce combines the answers. The
// combinations are exact, so the result is the single-process kernel's over the union of the
// shares, bit for bit, whatever the number of ranks or how the spheres are split:
// - closest hit: the minimum by (t, global id) of the ranks' closest hits (equal t: lower id);
// - occluded: the OR of the ranks' answers;
// - count_hits: the sum of the ranks' counts;
// - nearest: the minimum by (signed distance, global id), the point travelling with it.
// Within a rank the spheres are kept in ascending global id, so the kernel's own tie rule
// (lower local id) is the global one.
//
// Every query is collective: all ranks call it, in the same order, with batches of the same
// size. Construction is collective too. Destroy the scene before MPI_Finalize.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sphray/sphray.hpp"

namespace sphray::mpi {

/// Seconds spent, summed over the queries so far on this rank.
struct QueryTimes {
  double local = 0;   // tracing the rank's own spheres
  double reduce = 0;  // in MPI_Allreduce, waiting for slower ranks included
};

class DistributedScene {
 public:
  /// This rank's share: spheres[i] has global id global_ids[i]. Collective over comm. Throws
  /// std::invalid_argument if the sizes differ, an id is kNoHit or an id repeats on this rank
  /// (ids must be unique across ranks as well; that is the caller's promise), and
  /// std::runtime_error if the tree cannot be built (out of memory: a message naming the rank);
  /// the ranks agree first, so when one rank's share is refused every rank throws, with the
  /// message of the lowest rank refused.
  DistributedScene(MPI_Comm comm, SphereView spheres, std::span<const std::uint32_t> global_ids,
                   BvhBuildOptions options = {});
  ~DistributedScene();
  DistributedScene(const DistributedScene&) = delete;
  DistributedScene& operator=(const DistributedScene&) = delete;

  /// hits[i]: the closest hit of rays[i] over every rank's spheres, with its global id.
  void intersect(std::span<const Ray> rays, std::span<Hit> hits) const;
  /// out[i]: whether any rank's sphere is hit by rays[i] in (tmin, tmax).
  void occluded(std::span<const Ray> rays, std::span<bool> out) const;
  /// counts[i]: the crossings of rays[i] with every rank's spheres.
  void count_hits(std::span<const Ray> rays, std::span<std::size_t> counts) const;
  /// out[i]: the sphere nearest points[i] over every rank (id global), as sphray::nearest.
  void nearest(std::span<const Vec3> points, std::span<Nearest> out,
               float max_distance = kAnyDistance) const;

  std::size_t local_size() const { return ids_.size(); }
  std::size_t global_size() const { return global_size_; }
  /// Bytes this rank holds for the scene: its sphere copy, ids and tree.
  std::size_t local_bytes() const;
  /// Seconds this rank has spent building its tree.
  double build_seconds() const { return build_seconds_; }
  const QueryTimes& times() const { return times_; }
  MPI_Comm comm() const { return comm_; }

 private:
  template <typename Local, typename Reduce>
  void timed(Local&& local, Reduce&& reduce) const;

  MPI_Comm comm_;
  std::vector<std::uint32_t> ids_;  // global ids, ascending: local id i is global ids_[i]
  SphereBVH bvh_;
  std::size_t global_size_ = 0;
  double build_seconds_ = 0;
  mutable QueryTimes times_;
  MPI_Datatype hit_type_ = MPI_DATATYPE_NULL, nearest_type_ = MPI_DATATYPE_NULL;
  MPI_Op min_hit_ = MPI_OP_NULL, min_nearest_ = MPI_OP_NULL;
};

}  // namespace sphray::mpi
