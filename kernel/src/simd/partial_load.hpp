// The first n < width values of an array into a batch, zero in the other lanes, reading nothing
// past the n-th value: the last, partial batch of a view without padding.
//
// AVX-512 and AVX have masked loads that never touch (nor fault on) the lanes left out, and
// load straight into the register. Without them (SSE4.2, NEON) the caller copies the values
// into a zeroed stack batch and loads that: the scalar stores then the vector load defeat
// store-to-load forwarding, a stall paid once per ray on small unpadded views
// (docs/decisions.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include <xsimd/xsimd.hpp>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct PartialLoad {
  using Floats = xsimd::batch<float, A>;

  // Whether the instruction set has masked loads; without them, callers copy (see above).
#if defined(__x86_64__) || defined(__i386__)
  // (xsimd's avx512f derives from generic, not from avx: both are named.)
  static constexpr bool kMasked =
      std::is_base_of_v<xsimd::avx512f, A> || std::is_base_of_v<xsimd::avx, A>;
#else
  static constexpr bool kMasked = false;
#endif

  // p[0 .. n) into lanes 0 .. n, zeros above; 0 < n < width. Only where kMasked. T is 32-bit
  // (floats, masks) or double.
  template <class T>
  SPHRAY_FORCE_INLINE static xsimd::batch<T, A> load(const T* p, std::size_t n) {
    static_assert(kMasked && (sizeof(T) == sizeof(float) || std::is_same_v<T, double>));
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (std::is_same_v<T, double>) {
      if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
        return _mm512_maskz_loadu_pd(static_cast<__mmask8>((1u << n) - 1u), p);
      } else {
        const __m256i lanes = _mm256_cmpgt_epi64(_mm256_set1_epi64x(static_cast<long long>(n)),
                                                 _mm256_setr_epi64x(0, 1, 2, 3));
        return _mm256_maskload_pd(p, lanes);
      }
    } else if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
      const auto lanes = static_cast<__mmask16>((1u << n) - 1u);
      return as<T>(Floats(_mm512_maskz_loadu_ps(lanes, p)));
    } else {
      const __m256i lanes = _mm256_cmpgt_epi32(_mm256_set1_epi32(static_cast<int>(n)),
                                               _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
      return as<T>(Floats(_mm256_maskload_ps(reinterpret_cast<const float*>(p), lanes)));
    }
#endif
  }

 private:
  template <class T>
  SPHRAY_FORCE_INLINE static xsimd::batch<T, A> as(const Floats& x) {
    if constexpr (std::is_same_v<T, float>) {
      return x;
    } else {
      return xsimd::bitwise_cast<xsimd::batch<T, A>>(x);
    }
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
