// The kernel for SSE4.2 (4 lanes). Compiled with -msse4.2 only.
#include "dispatch/entry_points.hpp"

namespace sphray::detail {
constinit const Kernel kSse42Kernel = SPHRAY_ISA_NAMESPACE::make_kernel<xsimd::sse4_2>(Isa::sse4_2);
}
