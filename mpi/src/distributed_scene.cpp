#include "sphray/mpi/distributed_scene.hpp"

#include <algorithm>
#include <new>
#include <numeric>
#include <stdexcept>
#include <string>

#include "reductions.hpp"
#include "routing.hpp"
#include "sphray/mpi/agreement.hpp"

namespace sphray::mpi {
namespace {

// The rank's spheres in ascending global id, so that the kernel's tie rule on local ids (the
// lower one) agrees with the global rule.
SphereSoA sorted_by_id(SphereView spheres, std::span<const std::uint32_t> ids,
                       std::vector<std::uint32_t>& sorted_ids) {
  std::vector<std::size_t> order(ids.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return ids[a] < ids[b]; });
  SphereSoA sorted;
  sorted.reserve(ids.size());
  sorted_ids.resize(ids.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t i = order[k];
    if (ids[i] == kNoHit) throw std::invalid_argument("sphere id: kNoHit is not an id");
    if (k > 0 && ids[i] == sorted_ids[k - 1])
      throw std::invalid_argument("sphere id " + std::to_string(ids[i]) + " given twice");
    sorted_ids[k] = ids[i];
    sorted.add({spheres.cx[i], spheres.cy[i], spheres.cz[i]}, spheres.radius[i],
               spheres.mask != nullptr ? spheres.mask[i] : kAllBits);
  }
  return sorted;
}

MPI_Datatype bytes_type(std::size_t bytes) {
  MPI_Datatype type;
  MPI_Type_contiguous(static_cast<int>(bytes), MPI_BYTE, &type);
  MPI_Type_commit(&type);
  return type;
}

}  // namespace

DistributedScene::DistributedScene(MPI_Comm comm, SphereView spheres,
                                   std::span<const std::uint32_t> global_ids,
                                   BvhBuildOptions options)
    : comm_(comm), buffers_(std::make_unique<detail::RouteBuffers>()) {
  // A share refused on one rank must stop every rank, or the others would wait for it in the
  // first reduction: the ranks agree on the outcome, and every rank throws the first failing
  // rank's message.
  enum Refusal : int { kNone = 0, kInvalid = 1, kFailed = 2 };
  RankError mine;
  RegionBox region;
  int rank = 0;
  MPI_Comm_rank(comm_, &rank);
  const double start = MPI_Wtime();
  try {
    if (global_ids.size() != spheres.count)
      throw std::invalid_argument("expected one global id per sphere");
    const SphereSoA local = sorted_by_id(spheres, global_ids, ids_);
    bvh_ = SphereBVH(local.view(), options);
    region = region_box(local.view());
  } catch (const std::invalid_argument& e) {
    mine = {kInvalid, e.what()};
  } catch (const std::bad_alloc&) {
    mine = {kFailed, "out of memory building rank " + std::to_string(rank) + "'s tree over " +
                         std::to_string(spheres.count) + " spheres"};
  } catch (const std::exception& e) {  // std::length_error from the tree
    mine = {kFailed, e.what()};
  }
  build_seconds_ = MPI_Wtime() - start;
  const RankError first = first_error(comm_, mine);
  if (first.status == kInvalid) throw std::invalid_argument(first.message);
  if (first.status != kNone) throw std::runtime_error(first.message);
  unsigned long long count = ids_.size(), total = 0;
  MPI_Allreduce(&count, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm_);
  global_size_ = static_cast<std::size_t>(total);
  int ranks = 1;
  MPI_Comm_size(comm_, &ranks);
  regions_.resize(static_cast<std::size_t>(ranks));
  MPI_Allgather(&region, sizeof region, MPI_BYTE, regions_.data(), sizeof region, MPI_BYTE, comm_);
  hit_type_ = bytes_type(sizeof(Hit));
  nearest_type_ = bytes_type(sizeof(Nearest));
  travelling_type_ = bytes_type(detail::kTravellingBytes);
  MPI_Op_create(detail::min_hit, /*commute=*/1, &min_hit_);
  MPI_Op_create(detail::min_nearest, /*commute=*/1, &min_nearest_);
  // Messages of its own, which no receive of the caller's on comm can take.
  MPI_Comm_dup(comm_, &route_comm_);
}

DistributedScene::~DistributedScene() {
  MPI_Comm_free(&route_comm_);
  MPI_Op_free(&min_nearest_);
  MPI_Op_free(&min_hit_);
  MPI_Type_free(&nearest_type_);
  MPI_Type_free(&hit_type_);
  MPI_Type_free(&travelling_type_);
}

std::size_t DistributedScene::local_bytes() const {
  return bvh_.memory_bytes() + ids_.size() * sizeof(std::uint32_t);
}

template <typename Local, typename Reduce>
void DistributedScene::timed(Local&& local, Reduce&& reduce) const {
  const double start = MPI_Wtime();
  local();
  const double traced = MPI_Wtime();
  reduce();
  times_.local += traced - start;
  times_.reduce += MPI_Wtime() - traced;
}

void DistributedScene::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
  timed(
      [&] {
        sphray::intersect(bvh_, rays, hits);
        for (Hit& hit : hits)
          if (hit.found()) hit.id = ids_[hit.id];
      },
      [&] {
        detail::allreduce_in_place(hits.data(), hits.size(), sizeof(Hit), hit_type_, min_hit_,
                                   comm_);
      });
}

void DistributedScene::occluded(std::span<const Ray> rays, std::span<bool> out) const {
  if (out.size() != rays.size()) throw std::length_error("occluded: expected one answer per ray");
  timed([&] { sphray::occluded(bvh_, rays, out); },  // the stream: shadow rays go as packets
        [&] {
          detail::allreduce_in_place(out.data(), out.size(), sizeof(bool), MPI_C_BOOL, MPI_LOR,
                                     comm_);
        });
}

void DistributedScene::count_hits(std::span<const Ray> rays, std::span<std::size_t> counts) const {
  static_assert(sizeof(std::size_t) == sizeof(std::uint64_t));
  timed([&] { sphray::count_hits(bvh_, rays, counts); },
        [&] {
          detail::allreduce_in_place(counts.data(), counts.size(), sizeof(std::uint64_t),
                                     MPI_UINT64_T, MPI_SUM, comm_);
        });
}

void DistributedScene::nearest(std::span<const Vec3> points, std::span<Nearest> out,
                               float max_distance) const {
  timed(
      [&] {
        sphray::nearest(bvh_, points, out, max_distance);
        for (Nearest& n : out)
          if (n.found()) n.id = ids_[n.id];
      },
      [&] {
        detail::allreduce_in_place(out.data(), out.size(), sizeof(Nearest), nearest_type_,
                                   min_nearest_, comm_);
      });
}

}  // namespace sphray::mpi
