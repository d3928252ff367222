// The record a routed ray travels in between ranks, and the sparse exchange that moves a wave
// of them (MPI_Alltoallv).
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
  std::uint32_t owner;  // the rank that asked
  std::uint32_t index;  // the ray's index in its owner's batch
  std::uint32_t home;   // 1: the answer, on its way back to its owner
};

inline constexpr std::size_t kTravellingBytes = sizeof(Travelling);

/// A scene's scratch for the routed queries, kept between calls so that a query allocates
/// only when its batch grows.
struct RouteBuffers {
  std::vector<std::vector<Travelling>> outgoing;  // per destination rank
  std::vector<Travelling> sent, received, here, visiting;
  std::vector<Ray> rays;
  std::vector<Hit> hits, answers;
  std::unique_ptr<bool[]> blocked;
  std::size_t blocked_capacity = 0;
};

/// Sends outgoing[r] to rank r, for every r; buffers.received gets what every rank sent this
/// one, in rank order, and outgoing is left empty. Collective over comm. type: kTravellingBytes
/// bytes.
void exchange(std::vector<std::vector<Travelling>>& outgoing, RouteBuffers& buffers,
              MPI_Datatype type, MPI_Comm comm);

}  // namespace sphray::mpi::detail
