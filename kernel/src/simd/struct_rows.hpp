// The first eight floats of kWidth consecutive structs, one field per batch: field[j] lane k is
// base[k * stride + j]; and batches stored back as consecutive pairs. Each struct's eight floats
// are loaded as one row and the rows transposed in registers: some 50 instructions for 16 structs
// on AVX-512 where the eight fields' gathers (simd/stride_gather.hpp) issue sixteen gather
// instructions, the larger part of a stream's time on a view of few spheres. Moves only: no bit
// changes. Class template over A, like everything the per-ISA units include.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include <xsimd/xsimd.hpp>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/stride_gather.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct StructRows {
  using Floats = xsimd::batch<float, A>;
  static constexpr std::size_t kWidth = Floats::size;

  // base + (kWidth - 1) * stride + 8 floats must be readable; stride >= 8.
  SPHRAY_FORCE_INLINE static void first_eight(const float* base, std::size_t stride,
                                              Floats (&field)[8]) {
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
      // Row k and row k + 8 side by side in a register: the 8x8 transpose's in-lane steps then
      // serve both halves at once.
      __m512 v[8];
      for (std::size_t k = 0; k < 8; ++k) {
        const __m256 lo = _mm256_loadu_ps(base + k * stride);
        const __m256 hi = _mm256_loadu_ps(base + (k + 8) * stride);
        v[k] = _mm512_castpd_ps(_mm512_insertf64x4(_mm512_castps_pd(_mm512_castps256_ps512(lo)),
                                                   _mm256_castps_pd(hi), 1));
      }
      __m512 t[8], s[8];
      for (int i = 0; i < 8; i += 2) {
        t[i] = _mm512_unpacklo_ps(v[i], v[i + 1]);
        t[i + 1] = _mm512_unpackhi_ps(v[i], v[i + 1]);
      }
      for (int i = 0; i < 8; i += 4) {
        s[i] = _mm512_shuffle_ps(t[i], t[i + 2], 0x44);
        s[i + 1] = _mm512_shuffle_ps(t[i], t[i + 2], 0xEE);
        s[i + 2] = _mm512_shuffle_ps(t[i + 1], t[i + 3], 0x44);
        s[i + 3] = _mm512_shuffle_ps(t[i + 1], t[i + 3], 0xEE);
      }
      // 128-bit lanes (a0, b0, a2, b2) for fields 0-3, (a1, b1, a3, b3) for fields 4-7.
      const __m512i low =
          _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 8, 9, 10, 11, 24, 25, 26, 27);
      const __m512i high =
          _mm512_setr_epi32(4, 5, 6, 7, 20, 21, 22, 23, 12, 13, 14, 15, 28, 29, 30, 31);
      for (int j = 0; j < 4; ++j) {
        field[j] = _mm512_permutex2var_ps(s[j], low, s[j + 4]);
        field[j + 4] = _mm512_permutex2var_ps(s[j], high, s[j + 4]);
      }
      return;
    } else if constexpr (std::is_base_of_v<xsimd::avx, A>) {
      __m256 t[8], s[8];
      for (int i = 0; i < 8; i += 2) {
        const __m256 a = _mm256_loadu_ps(base + i * stride);
        const __m256 b = _mm256_loadu_ps(base + (i + 1) * stride);
        t[i] = _mm256_unpacklo_ps(a, b);
        t[i + 1] = _mm256_unpackhi_ps(a, b);
      }
      for (int i = 0; i < 8; i += 4) {
        s[i] = _mm256_shuffle_ps(t[i], t[i + 2], 0x44);
        s[i + 1] = _mm256_shuffle_ps(t[i], t[i + 2], 0xEE);
        s[i + 2] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0x44);
        s[i + 3] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0xEE);
      }
      for (int j = 0; j < 4; ++j) {
        field[j] = _mm256_permute2f128_ps(s[j], s[j + 4], 0x20);
        field[j + 4] = _mm256_permute2f128_ps(s[j], s[j + 4], 0x31);
      }
      return;
    } else if constexpr (std::is_base_of_v<xsimd::sse2, A>) {
      for (int half = 0; half < 2; ++half) {
        __m128 r0 = _mm_loadu_ps(base + 4 * half), r1 = _mm_loadu_ps(base + stride + 4 * half);
        __m128 r2 = _mm_loadu_ps(base + 2 * stride + 4 * half);
        __m128 r3 = _mm_loadu_ps(base + 3 * stride + 4 * half);
        _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
        field[4 * half] = r0, field[4 * half + 1] = r1;
        field[4 * half + 2] = r2, field[4 * half + 3] = r3;
      }
      return;
    }
#endif
    for (std::size_t j = 0; j < 8; ++j)
      field[j] = StrideGather<A>::load(base + j, static_cast<std::int32_t>(stride));
  }

  // The other way for structs of two 4-byte fields: a[k] and b[k] as the k-th pair at `to`,
  // for every lane k (a batch of {t, id} hits, the id's bits in b). The x86 forms store
  // through the intrinsics' vector types, which may alias anything. Interleaved in registers and
  // stored whole; xsimd's zip_lo/zip_hi interleave within 128-bit lanes only.
  SPHRAY_FORCE_INLINE static void store_pairs(void* to, const Floats& a, const Floats& b) {
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
      const __m512 lo = _mm512_unpacklo_ps(a, b), hi = _mm512_unpackhi_ps(a, b);
      const __m512i first =
          _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 4, 5, 6, 7, 20, 21, 22, 23);
      const __m512i second =
          _mm512_setr_epi32(8, 9, 10, 11, 24, 25, 26, 27, 12, 13, 14, 15, 28, 29, 30, 31);
      float* const out = static_cast<float*>(to);
      _mm512_storeu_ps(out, _mm512_permutex2var_ps(lo, first, hi));
      _mm512_storeu_ps(out + 16, _mm512_permutex2var_ps(lo, second, hi));
      return;
    } else if constexpr (std::is_base_of_v<xsimd::avx, A>) {
      const __m256 lo = _mm256_unpacklo_ps(a, b), hi = _mm256_unpackhi_ps(a, b);
      float* const out = static_cast<float*>(to);
      _mm256_storeu_ps(out, _mm256_permute2f128_ps(lo, hi, 0x20));
      _mm256_storeu_ps(out + 8, _mm256_permute2f128_ps(lo, hi, 0x31));
      return;
    } else if constexpr (std::is_base_of_v<xsimd::sse2, A>) {
      float* const out = static_cast<float*>(to);
      _mm_storeu_ps(out, _mm_unpacklo_ps(a, b));
      _mm_storeu_ps(out + 4, _mm_unpackhi_ps(a, b));
      return;
    }
#endif
    // Bytes copied, not floats assigned: `to` may hold other types of the same size (a Hit's
    // id), which a float store would alias.
    alignas(A::alignment()) float pairs[2 * kWidth];
    alignas(A::alignment()) float first[kWidth], second[kWidth];
    a.store_aligned(first);
    b.store_aligned(second);
    for (std::size_t k = 0; k < kWidth; ++k)
      pairs[2 * k] = first[k], pairs[2 * k + 1] = second[k];
    std::memcpy(to, pairs, sizeof pairs);
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
