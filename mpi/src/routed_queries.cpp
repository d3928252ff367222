// DistributedScene's routed queries: each rank's own rays visit only the ranks whose region
// they cross, front to back, in waves of sparse exchanges (distributed_scene.hpp).
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "routing.hpp"
#include "sphray/mpi/distributed_scene.hpp"

namespace sphray::mpi {
namespace detail {

void exchange(std::vector<std::vector<Travelling>>& outgoing, RouteBuffers& buffers,
              MPI_Datatype type, MPI_Comm comm) {
  const std::size_t ranks = outgoing.size();
  std::vector<int> send_counts(ranks), receive_counts(ranks), send_at(ranks), receive_at(ranks);
  std::size_t sending = 0;
  for (std::size_t r = 0; r < ranks; ++r) {
    if (outgoing[r].size() > static_cast<std::size_t>(std::numeric_limits<int>::max()) - sending)
      throw std::length_error("routed query: more than 2^31 - 1 rays in one exchange");
    send_at[r] = static_cast<int>(sending);
    send_counts[r] = static_cast<int>(outgoing[r].size());
    sending += outgoing[r].size();
  }
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, comm);
  std::size_t receiving = 0;
  for (std::size_t r = 0; r < ranks; ++r) {
    receive_at[r] = static_cast<int>(receiving);
    receiving += static_cast<std::size_t>(receive_counts[r]);
  }
  buffers.sent.clear();
  for (std::vector<Travelling>& to_rank : outgoing) {
    buffers.sent.insert(buffers.sent.end(), to_rank.begin(), to_rank.end());
    to_rank.clear();
  }
  buffers.received.resize(receiving);
  MPI_Alltoallv(buffers.sent.data(), send_counts.data(), send_at.data(), type,
                buffers.received.data(), receive_counts.data(), receive_at.data(), type, comm);
}

}  // namespace detail

using detail::Travelling;

// Moves every ray through its regions. visit(arrivals) answers a wave of rays that reached
// this rank, updating their best; a ray then goes to its next region, or home when none is
// left (or, with stop_at_hit, once it has a hit). A region is skipped when it starts beyond
// the nearest hit so far, which is exact: every hit in it has t at least its entry.
template <typename Visit>
void DistributedScene::route(std::span<const Ray> rays, Visit&& visit, bool stop_at_hit,
                             std::span<Hit> answers) const {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm_, &rank);
  MPI_Comm_size(comm_, &ranks);
  const auto me = static_cast<std::uint32_t>(rank);
  detail::RouteBuffers& buffers = *buffers_;
  std::vector<std::vector<Travelling>>& outgoing = buffers.outgoing;
  outgoing.resize(static_cast<std::size_t>(ranks));
  for (std::vector<Travelling>& to_rank : outgoing)
    to_rank.clear();  // a call refused below leaves records behind
  // Rays bound for this rank and answers owed to it never enter an exchange.
  std::vector<Travelling>& here = buffers.here;
  here.clear();
  const auto send_on = [&](Travelling& t, RegionKey after) {
    const bool found = t.best.found();
    const float bound = found ? t.best.t : t.ray.tmax;
    const RegionKey next =
        found && stop_at_hit ? RegionKey{0, -1} : next_region(regions_, t.ray, bound, after);
    t.home = next.region < 0 ? 1 : 0;
    t.entry = next.entry;
    const std::uint32_t to = t.home ? t.owner : static_cast<std::uint32_t>(next.region);
    if (to != me)
      outgoing[to].push_back(t);
    else if (t.home)
      answers[t.index] = t.best;
    else
      here.push_back(t);
  };
  const double first = MPI_Wtime();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    Travelling t{rays[i], {rays[i].tmax, kNoHit}, 0.0f, me, static_cast<std::uint32_t>(i), 0};
    send_on(t, RegionKey{});
  }
  counts_.asked += rays.size();
  times_.local += MPI_Wtime() - first;
  std::vector<Travelling>& visiting = buffers.visiting;
  for (;;) {
    const double start = MPI_Wtime();
    unsigned long long pending = here.size();
    for (const auto& to_rank : outgoing)
      pending += to_rank.size();
    counts_.sent += pending - here.size();
    MPI_Allreduce(MPI_IN_PLACE, &pending, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm_);
    if (pending == 0) {
      times_.reduce += MPI_Wtime() - start;
      break;
    }
    // Every rank sees the same total, so every rank refuses together. Below it, no count or
    // index of an exchange overflows an int, nor a ray's index its 32 bits.
    if (pending > static_cast<unsigned long long>(std::numeric_limits<int>::max()))
      throw std::length_error("routed query: more than 2^31 - 1 rays in flight at once");
    detail::exchange(outgoing, buffers, travelling_type_, comm_);
    ++counts_.waves;
    const double traced = MPI_Wtime();
    times_.reduce += traced - start;
    visiting.swap(here);  // here is empty from now on: a ray never visits a region twice
    here.clear();
    for (const Travelling& t : buffers.received) {
      if (t.home)
        answers[t.index] = t.best;
      else
        visiting.push_back(t);
    }
    visit(std::span<Travelling>(visiting));
    counts_.traced += visiting.size();
    for (Travelling& t : visiting)
      send_on(t, RegionKey{t.entry, rank});
    times_.local += MPI_Wtime() - traced;
  }
}

void DistributedScene::intersect_routed(std::span<const Ray> rays, std::span<Hit> hits) const {
  if (hits.size() != rays.size())
    throw std::length_error("intersect_routed: expected one hit per ray");
  std::vector<Ray>& bounded = buffers_->rays;
  std::vector<Hit>& local = buffers_->hits;
  const auto visit = [&](std::span<Travelling> arrivals) {
    bounded.resize(arrivals.size());
    local.resize(arrivals.size());
    for (std::size_t k = 0; k < arrivals.size(); ++k)
      bounded[k] = bounded_by(arrivals[k].ray, arrivals[k].best);
    sphray::intersect(bvh_, bounded, local);
    for (std::size_t k = 0; k < arrivals.size(); ++k)
      if (local[k].found()) keep_nearer(arrivals[k].best, {local[k].t, ids_[local[k].id]});
  };
  route(rays, visit, /*stop_at_hit=*/false, hits);
}

void DistributedScene::occluded_routed(std::span<const Ray> rays, std::span<bool> out) const {
  if (out.size() != rays.size())
    throw std::length_error("occluded_routed: expected one answer per ray");
  std::vector<Ray>& asked = buffers_->rays;
  std::unique_ptr<bool[]>& blocked = buffers_->blocked;
  std::size_t& capacity = buffers_->blocked_capacity;
  const auto visit = [&](std::span<Travelling> arrivals) {
    asked.resize(arrivals.size());
    if (arrivals.size() > capacity) {
      capacity = arrivals.size();
      blocked = std::make_unique<bool[]>(capacity);
    }
    for (std::size_t k = 0; k < arrivals.size(); ++k)
      asked[k] = arrivals[k].ray;
    sphray::occluded(bvh_, asked, std::span<bool>(blocked.get(), arrivals.size()));
    for (std::size_t k = 0; k < arrivals.size(); ++k)
      if (blocked[k]) arrivals[k].best = Hit{0.0f, 0};  // any hit: found() is the answer
  };
  std::vector<Hit>& answers = buffers_->answers;
  answers.resize(rays.size());
  route(rays, visit, /*stop_at_hit=*/true, answers);
  for (std::size_t i = 0; i < rays.size(); ++i)
    out[i] = answers[i].found();
}

}  // namespace sphray::mpi
