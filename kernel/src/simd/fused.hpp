// a * b + c, a * b - c and c - a * b rounded once, per lane of floats or doubles, on every
// architecture whose instruction set has a fused multiply-add. Class template over A, like
// everything the per-ISA units include.
//
// Only tests that decide no result use them (the batch pre-test SphereLanes::may_hit):
// the roots are computed without fused operations, so that every instruction set and the
// scalar reference make the same roundings. xsimd 8.1 has no AVX-512 fma: its generic fallback
// is a * b + c, which a compiler contracts to one instruction or not depending on what it
// inlined where. The kernel is built with -ffp-contract=off and asks for each fused operation
// here.
#pragma once

#include <type_traits>

#include <xsimd/xsimd.hpp>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include "simd/isa_namespace.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A, class S = float>
struct Fused {
  using Floats = xsimd::batch<S, A>;
#if defined(__x86_64__) || defined(__i386__)
  static constexpr bool kAvx512 = std::is_base_of_v<xsimd::avx512f, A>;
#else
  static constexpr bool kAvx512 = false;
#endif
  static constexpr bool kFloat = std::is_same_v<S, float>;

  static Floats fma(const Floats& a, const Floats& b, const Floats& c) {
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (kAvx512 && kFloat) return _mm512_fmadd_ps(a, b, c);
    if constexpr (kAvx512 && !kFloat) return _mm512_fmadd_pd(a, b, c);
#endif
    return xsimd::fma(a, b, c);
  }

  static Floats fms(const Floats& a, const Floats& b, const Floats& c) {
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (kAvx512 && kFloat) return _mm512_fmsub_ps(a, b, c);
    if constexpr (kAvx512 && !kFloat) return _mm512_fmsub_pd(a, b, c);
#endif
    return xsimd::fms(a, b, c);
  }

  // c - a * b.
  static Floats fnma(const Floats& a, const Floats& b, const Floats& c) {
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (kAvx512 && kFloat) return _mm512_fnmadd_ps(a, b, c);
    if constexpr (kAvx512 && !kFloat) return _mm512_fnmadd_pd(a, b, c);
#endif
    return xsimd::fnma(a, b, c);
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
