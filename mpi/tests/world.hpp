// This process's rank and the rank count of MPI_COMM_WORLD, for the MPI tests.
#pragma once

#include <mpi.h>

namespace sphray::mpi::test {

inline int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

inline int ranks() {
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

}  // namespace sphray::mpi::test
