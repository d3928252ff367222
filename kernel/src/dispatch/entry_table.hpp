// The kernels this build has, one per instruction set, each defined in its own translation unit
// compiled with exactly that instruction set's flags (see CMakeLists.txt).
#pragma once

#include "sphray/isa.hpp"

namespace sphray::detail {

extern const Kernel kScalarKernel;
#if SPHRAY_HAS_SSE4_2
extern const Kernel kSse42Kernel;
#endif
#if SPHRAY_HAS_AVX2
extern const Kernel kAvx2Kernel;
#endif
#if SPHRAY_HAS_AVX512
extern const Kernel kAvx512Kernel;
#endif
#if SPHRAY_HAS_NEON
extern const Kernel kNeonKernel;
#endif

}  // namespace sphray::detail
