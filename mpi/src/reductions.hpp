// The reductions that combine the ranks' answers to one query batch: user-defined MPI
// operations for the minimum hit by (t, id) and the minimum nearest sphere by (distance, id),
// and an in-place MPI_Allreduce for batches of any length.
#pragma once

#include <mpi.h>

#include <cstddef>

#include "sphray/sphray.hpp"

namespace sphray::mpi::detail {

/// Whether a comes first in the closest-hit order: smaller t, or equal t and a lower id. A miss
/// (id kNoHit, t = tmax) never comes before a hit of the same ray, whose t < tmax.
inline bool hit_before(const Hit& a, const Hit& b) {
  return a.t < b.t || (a.t == b.t && a.id < b.id);
}

/// Whether a comes first in the nearest order: smaller signed distance, or equal and lower id.
inline bool nearest_before(const Nearest& a, const Nearest& b) {
  return a.distance < b.distance || (a.distance == b.distance && a.id < b.id);
}

/// MPI_User_function: inout[i] = the first of in[i] and inout[i] by hit_before.
void min_hit(void* in, void* inout, int* count, MPI_Datatype* type);
/// MPI_User_function: inout[i] = the first of in[i] and inout[i] by nearest_before.
void min_nearest(void* in, void* inout, int* count, MPI_Datatype* type);

/// MPI_Allreduce(MPI_IN_PLACE, data, count, ...) for any count: batches longer than an int
/// counts are reduced in pieces. element_bytes is the extent of one element of type.
void allreduce_in_place(void* data, std::size_t count, std::size_t element_bytes, MPI_Datatype type,
                        MPI_Op op, MPI_Comm comm);

}  // namespace sphray::mpi::detail
