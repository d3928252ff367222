// The record a routed ray travels in between ranks, and the sparse exchange that moves a wave
// of them (point to point, between the ranks that have records for each other).
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "sphray/sphray.hpp"

namespace sphray::mpi::detail {

/// A ray on its way: to the next region it crosses, or home with its answer.
struct Travelling {
  Ray ray;              // as its owner passed it
  Hit best;             // the nearest hit so far (global id), {tmax, kNoHit} before any
  float entry;          // where the ray enters the region of the rank it is sent to
  float then;           // where it enters the region after that one (RegionSteps::then)
  std::uint32_t owner;  // the rank that asked
  std::uint32_t index;  // the ray's index in its owner's batch
  std::uint32_t home;   // 1: the answer, on its way back to its owner
};

inline constexpr std::size_t kTravellingBytes = sizeof(Travelling);

/// What a routed call asks: the closest hit (intersect_routed), any hit (occluded_routed), or
/// nothing (finish_routed: the rank only answers the others' rays, in their kind of query).
enum class Query : int { finishing, closest, any };

/// The rays a rank traces at once when it answers a wave: their records, bounded copies and
/// hits stay in the core's caches between the trace and the routing that follows it, however
/// large the wave.
inline constexpr std::size_t kVisitChunk = 4096;

/// A scene's scratch for the routed queries, kept between calls so that a query allocates
/// only when its batch grows.
struct RouteBuffers {
  std::vector<std::vector<Travelling>> outgoing;  // per destination rank
  std::vector<Travelling> received, starting;
  std::vector<int> send_counts, receive_counts;
  std::vector<MPI_Request> requests;
  std::vector<Ray> rays;
  std::vector<Hit> hits, answers;
  std::unique_ptr<bool[]> blocked;
  std::size_t blocked_capacity = 0;
};

/// The tag of the routed records' messages, on the scene's own communicator.
inline constexpr int kRouteTag = 1;

/// Sends outgoing[r] to rank r, for every r; buffers.received gets what every rank sent this
/// one, in rank order, and outgoing is left empty. Collective over comm (the counts), then
/// point to point between the ranks that have records for each other. type: kTravellingBytes
/// bytes.
void exchange(std::vector<std::vector<Travelling>>& outgoing, RouteBuffers& buffers,
              MPI_Datatype type, MPI_Comm comm);

}  // namespace sphray::mpi::detail
