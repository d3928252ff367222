// Memory a run will need, checked before the work that needs it: a render that cannot get the
// memory for its image is refused up front with the size it needed, instead of dying of
// std::bad_alloc after the work (or, worse, half-way through writing the file).
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace sphray::render {

/// Memory the process cannot get; what() is one line naming what needed it and how much.
class InsufficientMemory : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Whether bytes more memory can be had now: maps that much (private, read-write, never
/// touched) and unmaps it again. That is refused by an address-space limit (`ulimit -v`), by
/// strict overcommit accounting, and by the kernel's heuristic for an amount it could never
/// supply; what only touching the pages would find short (the OOM killer's domain) is not.
bool can_map(std::size_t bytes);

/// "3.2 GiB", "805 MiB": a size for messages.
std::string format_bytes(std::size_t bytes);

/// Throws InsufficientMemory ("<what> needs about N of memory, which this process cannot
/// get (...)") unless can_map(bytes).
void require_memory(std::size_t bytes, const std::string& what);

}  // namespace sphray::render
