// Lane k of a batch from src[k * stride] (one field of consecutive structs, read across them),
// or from src[index[k]]. xsimd's gather where it serves: gather instructions (AVX2), or loads
// into lanes (SSE4.2, NEON). On AVX-512, two 8-lane gathers joined: the 16-lane gather
// instructions measured far slower than that on AMD Zen 4 (docs/performance.md, "Rays across
// the lanes").
// Class template over A, like everything the per-ISA units include.
#pragma once

#include <cstdint>
#include <type_traits>

#include <xsimd/xsimd.hpp>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct StrideGather {
  using Ints = xsimd::batch<std::int32_t, A>;

  // T: float or std::uint32_t. src + (kWidth - 1) * stride must be readable.
  template <class T>
  static xsimd::batch<T, A> load(const T* src, std::int32_t stride) {
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) return halves(src, stride);
#endif
    const Ints at = xsimd::bitwise_cast<Ints>(LaneReduce<A>::lane_index()) * Ints(stride);
    return xsimd::batch<T, A>::gather(src, at);
  }

  // src[index[k]] for every lane k; every index must be readable.
  static xsimd::batch<float, A> at(const float* src, const Ints& index) {
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
      const __m512i all = index;
      return join(_mm256_i32gather_ps(src, _mm512_castsi512_si256(all), 4),
                  _mm256_i32gather_ps(src, _mm512_extracti64x4_epi64(all, 1), 4));
    }
#endif
    return xsimd::batch<float, A>::gather(src, index);
  }

 private:
#if defined(__x86_64__) || defined(__i386__)
  static __m256i first_eight(std::int32_t stride) {
    return _mm256_mullo_epi32(_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), _mm256_set1_epi32(stride));
  }
  static __m512 join(__m256 lo, __m256 hi) {
    return _mm512_castpd_ps(
        _mm512_insertf64x4(_mm512_castps_pd(_mm512_castps256_ps512(lo)), _mm256_castps_pd(hi), 1));
  }
  static __m512 halves(const float* src, std::int32_t stride) {
    const __m256i at = first_eight(stride);
    return join(_mm256_i32gather_ps(src, at, 4), _mm256_i32gather_ps(src + 8 * stride, at, 4));
  }
  static __m512i halves(const std::uint32_t* src, std::int32_t stride) {
    const __m256i at = first_eight(stride);
    const auto* base = reinterpret_cast<const int*>(src);
    const __m256i lo = _mm256_i32gather_epi32(base, at, 4);
    const __m256i hi = _mm256_i32gather_epi32(base + 8 * stride, at, 4);
    return _mm512_inserti64x4(_mm512_castsi256_si512(lo), hi, 1);
  }
#endif
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
