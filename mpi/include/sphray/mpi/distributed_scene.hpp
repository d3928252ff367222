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
// size. Construction is collective too. Destroy the scene before MPI_Finalize. A scene keeps
// counters and scratch for its queries: call them from one thread at a time.
//
// The routed queries (intersect_routed, occluded_routed) take each rank's own rays instead:
// every rank calls them, in the same order, but with its own batch of any size (0 included);
// ranks whose numbers of calls differ each end theirs with finish_routed(). A
// ray goes only to the ranks whose region (the box around their spheres, regions.hpp) its
// segment crosses, front to back, carrying the nearest hit so far, which bounds the next
// rank's search and skips the regions that start beyond it; the answer returns to the rank that
// asked. Exchanges are sparse (the rays a rank sends another, point to point on the scene's own
// communicator, a duplicate of comm's), one per wave of visits
// for the whole batch. Same answers, bit for bit, as the shared-batch queries.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "sphray/mpi/regions.hpp"
#include "sphray/sphray.hpp"

namespace sphray::mpi {
namespace detail {
struct RouteBuffers;
struct Travelling;
enum class Query : int;
}  // namespace detail

/// Seconds spent, summed over the queries so far on this rank.
struct QueryTimes {
  double local = 0;   // tracing the rank's own spheres
  double reduce = 0;  // in MPI_Allreduce or the routed exchanges, waiting for others included
};

/// What the routed queries did on this rank, summed over the calls so far.
struct RouteCounts {
  std::uint64_t asked = 0;   // rays this rank passed in
  std::uint64_t traced = 0;  // rays traced in this rank's tree (its own and others')
  std::uint64_t sent = 0;    // records this rank sent to other ranks (rays and answers)
  std::uint64_t waves = 0;   // exchanges
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

  /// As intersect, for this rank's own rays: collective, but each rank passes its own batch.
  /// Throws std::length_error on every rank when more than 2^31 - 1 rays would travel at once
  /// (the ranks' batches together).
  void intersect_routed(std::span<const Ray> rays, std::span<Hit> hits) const;
  /// As occluded, for this rank's own rays (collective, each rank its own batch).
  void occluded_routed(std::span<const Ray> rays, std::span<bool> out) const;
  /// For ranks that make different numbers of routed calls (a path tracer's bounces differ
  /// between the ranks' tiles): a rank that has made its last one calls this, which takes part
  /// in the other ranks' calls, answering the rays sent to its region, until every rank has
  /// called it; then it returns on every rank. Collective. Throws std::logic_error on every
  /// rank when, at one step, some ranks call intersect_routed and others occluded_routed.
  void finish_routed() const;
  /// The region of every rank, in rank order.
  std::span<const RegionBox> regions() const { return regions_; }
  const RouteCounts& route_counts() const { return counts_; }

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
  bool route(std::span<const Ray> rays, detail::Query query, std::span<Hit> answers) const;
  void visit(std::span<detail::Travelling> arrivals, detail::Query query) const;

  MPI_Comm comm_;
  MPI_Comm route_comm_ = MPI_COMM_NULL;  // comm's duplicate: the routed records' messages
  std::vector<std::uint32_t> ids_;       // global ids, ascending: local id i is global ids_[i]
  SphereBVH bvh_;
  std::size_t global_size_ = 0;
  double build_seconds_ = 0;
  std::vector<RegionBox> regions_;  // every rank's, in rank order
  mutable QueryTimes times_;
  mutable RouteCounts counts_;
  std::unique_ptr<detail::RouteBuffers> buffers_;  // the routed queries' scratch
  MPI_Datatype hit_type_ = MPI_DATATYPE_NULL, nearest_type_ = MPI_DATATYPE_NULL,
               travelling_type_ = MPI_DATATYPE_NULL;
  MPI_Op min_hit_ = MPI_OP_NULL, min_nearest_ = MPI_OP_NULL;
};

}  // namespace sphray::mpi
