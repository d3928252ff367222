// The kernel for SSE4.2 (4 lanes). Compiled with -msse4.2 only.
#include "dispatch/entry_points.hpp"

namespace sphray::detail {
constinit const EntryTable kSse42Entries =
    SPHRAY_ISA_NAMESPACE::make_entry_table<xsimd::sse4_2>(Isa::sse4_2);
}
