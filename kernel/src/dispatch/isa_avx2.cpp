// The kernel for AVX2 with FMA (8 lanes). Compiled with -mavx2 -mfma only.
#include "dispatch/entry_points.hpp"

namespace sphray::detail {
constinit const Kernel kAvx2Kernel =
    SPHRAY_ISA_NAMESPACE::make_kernel<xsimd::fma3<xsimd::avx2>>(Isa::avx2);
}
