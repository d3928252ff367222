// Which code answers a view of a given size: one rule, read by the per-ISA entry points, the
// dispatcher and the public queries.
#pragma once

#include <cstddef>

namespace sphray::detail {

// Views of fewer spheres go to the scalar loop on every path: a single sphere is tested faster
// by it than by a batch that is mostly padding; from two spheres on a 4-lane batch wins
// (measured in docs/performance.md).
inline constexpr std::size_t kScalarBelow = 2;

}  // namespace sphray::detail
