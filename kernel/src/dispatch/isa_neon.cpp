// The kernel for NEON on 64-bit ARM (4 lanes). NEON is part of the AArch64 baseline.
#include "dispatch/entry_points.hpp"

namespace sphray::detail {
constinit const Kernel kNeonKernel = SPHRAY_ISA_NAMESPACE::make_kernel<xsimd::neon64>(Isa::neon);
}
