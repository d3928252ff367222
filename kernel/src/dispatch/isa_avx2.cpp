// The kernel for AVX2 with FMA (8 lanes). Compiled with -mavx2 -mfma only.
#include "dispatch/entry_points.hpp"

namespace sphray::detail {
constinit const EntryTable kAvx2Entries =
    SPHRAY_ISA_NAMESPACE::make_entry_table<xsimd::fma3<xsimd::avx2>>(Isa::avx2);
}
