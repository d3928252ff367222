// DistributedScene's routed queries: each rank's own rays visit only the ranks whose region
// they cross, front to back, in waves of sparse exchanges (distributed_scene.hpp).
#include <algorithm>
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
  std::vector<int>& send_counts = buffers.send_counts;
  std::vector<int>& receive_counts = buffers.receive_counts;
  send_counts.resize(ranks);
  receive_counts.resize(ranks);
  for (std::size_t r = 0; r < ranks; ++r) {
    // The caller's count of the rays in flight keeps each below 2^31.
    send_counts[r] = static_cast<int>(outgoing[r].size());
  }
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, comm);
  std::size_t receiving = 0;
  for (int count : receive_counts)
    receiving += static_cast<std::size_t>(count);
  buffers.received.resize(receiving);
  // Point to point, each rank's records straight from its own buffer, and only between ranks
  // that have records for each other.
  std::vector<MPI_Request>& requests = buffers.requests;
  requests.clear();
  Travelling* into = buffers.received.data();
  for (std::size_t r = 0; r < ranks; ++r) {
    if (receive_counts[r] == 0) continue;
    requests.emplace_back();
    MPI_Irecv(into, receive_counts[r], type, static_cast<int>(r), kRouteTag, comm,
              &requests.back());
    into += receive_counts[r];
  }
  for (std::size_t r = 0; r < ranks; ++r) {
    if (send_counts[r] == 0) continue;
    requests.emplace_back();
    MPI_Isend(outgoing[r].data(), send_counts[r], type, static_cast<int>(r), kRouteTag, comm,
              &requests.back());
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  for (std::vector<Travelling>& to_rank : outgoing)
    to_rank.clear();
}

}  // namespace detail

using detail::Query;
using detail::Travelling;

// Moves every ray through its regions. A wave's arrivals are answered by visit(), which updates
// their best; a ray then goes to its next region, or home when none is left (or, for any hit,
// once it has one). A region is skipped when it starts beyond the nearest hit so far, which is
// exact: every hit in it has t at least its entry. Every wave begins with one MPI_Allreduce of
// the rays in flight and of the ranks asking each kind of query, so that a finishing rank
// (Query::finishing, no rays) learns which kind the others' rays need, and when every rank is
// finishing. Returns false when every rank was.
bool DistributedScene::route(std::span<const Ray> rays, Query query, std::span<Hit> answers) const {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm_, &rank);
  MPI_Comm_size(comm_, &ranks);
  const auto me = static_cast<std::uint32_t>(rank);
  detail::RouteBuffers& buffers = *buffers_;
  std::vector<std::vector<Travelling>>& outgoing = buffers.outgoing;
  outgoing.resize(static_cast<std::size_t>(ranks));
  for (std::vector<Travelling>& to_rank : outgoing)
    to_rank.clear();  // a call refused below leaves records behind
  // This rank's own rays that enter its region first: traced before any exchange, a chunk at a
  // time, so that their records never leave the caches.
  std::vector<Travelling>& starting = buffers.starting;
  starting.clear();
  // Where t goes after `after` (RegionKey{}: before any visit): to its next region, bounded by
  // its nearest hit so far, or home once none is left (or an any-hit query has its hit). After
  // a visit, the entry of the region after it, carried in the record, usually settles that
  // without a search.
  const auto send_on = [&](Travelling& t, RegionKey after) {
    const bool found = t.best.found();
    const float bound = found ? t.best.t : t.ray.tmax;
    RegionSteps steps;  // none: home
    if (!(found && query == Query::any) && (after.region < 0 || t.then <= reach(t.ray, bound)))
      steps = next_regions(regions_, t.ray, bound, after);
    t.home = steps.next.region < 0 ? 1 : 0;
    t.entry = steps.next.entry;
    t.then = steps.then;
    const std::uint32_t to = t.home ? t.owner : static_cast<std::uint32_t>(steps.next.region);
    if (to != me)
      outgoing[to].push_back(t);
    else if (t.home)
      answers[t.index] = t.best;
    else
      starting.push_back(t);  // only before its first visit: regions are met once, in order
  };
  // Traces rays that reached this region, in chunks, and sends each on.
  const auto visit_here = [&](std::span<Travelling> arrivals) {
    counts_.traced += arrivals.size();
    for (std::size_t begin = 0; begin < arrivals.size(); begin += detail::kVisitChunk) {
      const std::span<Travelling> chunk =
          arrivals.subspan(begin, std::min(detail::kVisitChunk, arrivals.size() - begin));
      visit(chunk, query);
      for (Travelling& t : chunk)
        send_on(t, RegionKey{t.entry, rank});
    }
  };
  const double first = MPI_Wtime();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    Travelling t{rays[i], {rays[i].tmax, kNoHit}, 0.0f, 0.0f, me, static_cast<std::uint32_t>(i), 0};
    send_on(t, RegionKey{});
    if (starting.size() == detail::kVisitChunk) {
      visit_here(starting);
      starting.clear();
    }
  }
  visit_here(starting);
  counts_.asked += rays.size();
  times_.local += MPI_Wtime() - first;
  for (bool first_wave = true;; first_wave = false) {
    const double start = MPI_Wtime();
    unsigned long long in_flight[3] = {0, query == Query::closest ? 1u : 0u,
                                       query == Query::any ? 1u : 0u};
    for (const auto& to_rank : outgoing)
      in_flight[0] += to_rank.size();
    counts_.sent += in_flight[0];
    MPI_Allreduce(MPI_IN_PLACE, in_flight, 3, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm_);
    if (first_wave) {
      // Every rank sees the same sums, so every rank throws or returns together.
      if (in_flight[1] > 0 && in_flight[2] > 0) {
        throw std::logic_error(
            "routed query: some ranks called intersect_routed and others occluded_routed");
      }
      if (query == Query::finishing) {
        if (in_flight[1] == 0 && in_flight[2] == 0) {
          times_.reduce += MPI_Wtime() - start;
          return false;
        }
        query = in_flight[1] > 0 ? Query::closest : Query::any;
      }
    }
    const unsigned long long pending = in_flight[0];
    if (pending == 0) {
      times_.reduce += MPI_Wtime() - start;
      break;
    }
    // Below this, no count or index of an exchange overflows an int, nor a ray's index its 32
    // bits.
    if (pending > static_cast<unsigned long long>(std::numeric_limits<int>::max()))
      throw std::length_error("routed query: more than 2^31 - 1 rays in flight at once");
    detail::exchange(outgoing, buffers, travelling_type_, route_comm_);
    ++counts_.waves;
    const double traced = MPI_Wtime();
    times_.reduce += traced - start;
    // Answers home; the rest visit this region, packed in place at the front.
    std::vector<Travelling>& received = buffers.received;
    std::size_t arrived = 0;
    for (std::size_t k = 0; k < received.size(); ++k) {
      if (received[k].home)
        answers[received[k].index] = received[k].best;
      else if (arrived++ != k)
        received[arrived - 1] = received[k];
    }
    visit_here(std::span(received.data(), arrived));
    times_.local += MPI_Wtime() - traced;
  }
  return true;
}

// Traces arrivals in this rank's tree, each bounded by its nearest hit so far: the closest hit,
// kept when nearer (global id), or any hit, which ends the ray's search.
void DistributedScene::visit(std::span<Travelling> arrivals, Query query) const {
  std::vector<Ray>& bounded = buffers_->rays;
  bounded.resize(arrivals.size());
  if (query == Query::closest) {
    std::vector<Hit>& local = buffers_->hits;
    local.resize(arrivals.size());
    for (std::size_t k = 0; k < arrivals.size(); ++k)
      bounded[k] = bounded_by(arrivals[k].ray, arrivals[k].best);
    sphray::intersect(bvh_, bounded, local);
    for (std::size_t k = 0; k < arrivals.size(); ++k)
      if (local[k].found()) keep_nearer(arrivals[k].best, {local[k].t, ids_[local[k].id]});
    return;
  }
  // The rays reach this rank only while they have no hit: their own bounds.
  std::unique_ptr<bool[]>& blocked = buffers_->blocked;
  std::size_t& capacity = buffers_->blocked_capacity;
  if (arrivals.size() > capacity) {
    capacity = arrivals.size();
    blocked = std::make_unique<bool[]>(capacity);
  }
  for (std::size_t k = 0; k < arrivals.size(); ++k)
    bounded[k] = arrivals[k].ray;
  sphray::occluded(bvh_, bounded, std::span<bool>(blocked.get(), arrivals.size()));
  for (std::size_t k = 0; k < arrivals.size(); ++k)
    if (blocked[k]) arrivals[k].best = Hit{0.0f, 0};  // any hit: found() is the answer
}

void DistributedScene::intersect_routed(std::span<const Ray> rays, std::span<Hit> hits) const {
  if (hits.size() != rays.size())
    throw std::length_error("intersect_routed: expected one hit per ray");
  route(rays, Query::closest, hits);
}

void DistributedScene::occluded_routed(std::span<const Ray> rays, std::span<bool> out) const {
  if (out.size() != rays.size())
    throw std::length_error("occluded_routed: expected one answer per ray");
  std::vector<Hit>& answers = buffers_->answers;
  answers.resize(rays.size());
  route(rays, Query::any, answers);
  for (std::size_t i = 0; i < rays.size(); ++i)
    out[i] = answers[i].found();
}

void DistributedScene::finish_routed() const {
  while (route({}, Query::finishing, {})) {
  }
}

}  // namespace sphray::mpi
