#include "reductions.hpp"

#include <algorithm>
#include <cstring>

namespace sphray::mpi::detail {
namespace {

// Element by element through copies: MPI hands the buffers over as void*, with no promise of
// the element type's alignment for its own temporaries.
template <typename T, bool (*before)(const T&, const T&)>
void keep_first(void* in, void* inout, int count) {
  const auto* source = static_cast<const unsigned char*>(in);
  auto* target = static_cast<unsigned char*>(inout);
  for (int i = 0; i < count; ++i) {
    T a, b;
    std::memcpy(&a, source + i * sizeof(T), sizeof(T));
    std::memcpy(&b, target + i * sizeof(T), sizeof(T));
    if (before(a, b)) std::memcpy(target + i * sizeof(T), &a, sizeof(T));
  }
}

}  // namespace

void min_hit(void* in, void* inout, int* count, MPI_Datatype*) {
  keep_first<Hit, hit_before>(in, inout, *count);
}

void min_nearest(void* in, void* inout, int* count, MPI_Datatype*) {
  keep_first<Nearest, nearest_before>(in, inout, *count);
}

void allreduce_in_place(void* data, std::size_t count, std::size_t element_bytes, MPI_Datatype type,
                        MPI_Op op, MPI_Comm comm) {
  constexpr std::size_t kPiece = std::size_t{1} << 26;  // elements: well inside an int
  auto* bytes = static_cast<unsigned char*>(data);
  // Every rank has the same count, so every rank makes the same calls.
  for (std::size_t done = 0; done < count;) {
    const std::size_t piece = std::min(kPiece, count - done);
    MPI_Allreduce(MPI_IN_PLACE, bytes + done * element_bytes, static_cast<int>(piece), type, op,
                  comm);
    done += piece;
  }
}

}  // namespace sphray::mpi::detail
