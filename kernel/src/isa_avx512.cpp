// The kernel for AVX-512F (16 lanes). Compiled with -mavx512f -mfma only.

// g++ 12's avx512fintrin.h initialises the pass-through operand of _mm512_sqrt_ps, _min_ps and
// _max_ps from _mm512_undefined_ps(), which -Wmaybe-uninitialized wrongly reports once inlined
// (GCC bug 105593, fixed in g++ 13).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "kernel_entries.hpp"

namespace sphray::detail {
constinit const Kernel kAvx512Kernel = make_kernel<xsimd::avx512f>(Isa::avx512);
}
