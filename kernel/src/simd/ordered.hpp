// a < b ? a : b and a > b ? a : b per lane (float or double), the second operand whenever either is
// NaN, on every architecture. Class template over A, like everything the per-ISA units include.
//
// On x86 this is what minps/minpd and maxps/maxpd do (the Intel SDM defines them as exactly these
// comparisons), so one instruction, where a compare and a blend slowed a tree's leaf test
// (docs/history.md, "The kernel without FMA"). NEON's vminq/vmaxq return NaN instead, so other
// architectures compare and select.
#pragma once

#include <xsimd/xsimd.hpp>

#include "simd/isa_namespace.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct Ordered {
  using Floats = xsimd::batch<S, A>;

  static Floats less_or_second(const Floats& a, const Floats& b) {
#if defined(__x86_64__) || defined(__i386__)
    return xsimd::min(a, b);
#else
    return xsimd::select(a < b, a, b);
#endif
  }

  static Floats greater_or_second(const Floats& a, const Floats& b) {
#if defined(__x86_64__) || defined(__i386__)
    return xsimd::max(a, b);
#else
    return xsimd::select(a > b, a, b);
#endif
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
