// The kernel for NEON on 64-bit ARM (4 lanes). NEON is part of the AArch64 baseline.
#include "dispatch/entry_points.hpp"

namespace sphray::detail {
constinit const EntryTable kNeonEntries =
    SPHRAY_ISA_NAMESPACE::make_entry_table<xsimd::neon64>(Isa::neon);
}
