// Where overlapping() puts the ids it finds: the lowest capacity of them, in a max-heap while
// the query runs and sorted when it ends, and how many there were in all; and where
// overlapping_pairs() puts its pairs. Shared by every
// instruction set's unit, so its functions are never inline (simd/isa_namespace.hpp): a call
// per overlapping sphere, which is the output's own cost anyway.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sphray/point_queries.hpp"

namespace sphray::detail {

struct IdCollector {
  std::uint32_t* ids;    // the caller's span
  std::size_t capacity;  // its size
  bool first_only;       // inside(): one is enough, stop there
  std::size_t size = 0;  // ids held, at most capacity
  std::size_t total = 0;

  /// Counts id and keeps it if it is among the lowest capacity so far. Returns whether the
  /// query may stop (first_only and one found).
  bool add(std::uint32_t id);
  /// Sorts the ids held, ascending.
  void finish();
};

/// Appends the pair {first, second} to out: for overlapping_pairs(), out of line for the same
/// reason (an inlined push_back would leave std::vector's growth as a weak symbol that every
/// instruction set's unit defines).
void append_pair(std::vector<IdPair>& out, std::uint32_t first, std::uint32_t second);

}  // namespace sphray::detail
