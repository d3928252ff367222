// The kernel for AVX-512F (16 lanes). Compiled with -mavx512f -mfma only.

// g++ 12's avx512fintrin.h initialises the pass-through operand of _mm512_sqrt_ps, _min_ps and
// _max_ps from _mm512_undefined_ps(), which -Wmaybe-uninitialized wrongly reports once inlined
// (GCC bug 105593, fixed in g++ 13); with -fsanitize=address it reports -Wuninitialized
// instead. clang has neither false positive, and does not know the first warning's name.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif

#include "dispatch/entry_points.hpp"

namespace sphray::detail {
constinit const EntryTable kAvx512Entries =
    SPHRAY_ISA_NAMESPACE::make_entry_table<xsimd::avx512f>(Isa::avx512);
}
