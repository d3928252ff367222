// Horizontal reductions across the lanes of one xsimd batch, once per ray (xsimd 8.1 has no
// reduce_min). Class templates over A, like everything the per-ISA units instantiate.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>  // the mask move of each width, whatever this unit's flags
#endif

#include "simd/isa_namespace.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct LaneReduce {
  template <class T>
  using Batch = xsimd::batch<T, A>;
  static constexpr std::size_t kWidth = Batch<float>::size;

  // The lane index i ^ kStride: swapping halves, then quarters, ... of the batch, as lanes of
  // 32 or 64 bits (Index).
  template <std::size_t kStride, class Index = std::uint32_t>
  struct XorLane {
    static constexpr Index get(std::size_t i, std::size_t) {
      return static_cast<Index>(i ^ kStride);
    }
  };

  // Every lane gets the minimum over all lanes: log2(width) swap-and-min steps, no branch.
  template <class T, std::size_t kStride = Batch<T>::size / 2>
  static Batch<T> all_min(Batch<T> x) {
    if constexpr (kStride == 0)
      return x;
    else
      return all_min<T, kStride / 2>(xsimd::min(x, swapped<kStride>(x)));
  }

  // x with lane i moved to lane i ^ kStride. On x86 a swap within 128 bits is an in-lane
  // shuffle (1 cycle) rather than the full permute xsimd's swizzle emits (3 cycles): the BVH's
  // leaf fold waits on all_min.
  template <std::size_t kStride, class T>
  static Batch<T> swapped(const Batch<T>& x) {
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (sizeof(T) == 4) {
      Batch<float> f, r;
      if constexpr (std::is_same_v<T, float>)  // xsimd 8.1 casts only between different types
        f = x;
      else
        f = xsimd::bitwise_cast<Batch<float>>(x);
      if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
        const __m512 v = f;
        if constexpr (kStride == 8)
          r = _mm512_shuffle_f32x4(v, v, 0x4e);  // 128-bit blocks 2 3 0 1
        else if constexpr (kStride == 4)
          r = _mm512_shuffle_f32x4(v, v, 0xb1);  // blocks 1 0 3 2
        else
          r = _mm512_permute_ps(v, kStride == 2 ? 0x4e : 0xb1);
      } else if constexpr (std::is_base_of_v<xsimd::avx, A>) {
        const __m256 v = f;
        if constexpr (kStride == 4)
          r = _mm256_permute2f128_ps(v, v, 0x01);
        else
          r = _mm256_permute_ps(v, kStride == 2 ? 0x4e : 0xb1);
      } else {
        const __m128 v = f;
        r = _mm_shuffle_ps(v, v, kStride == 2 ? 0x4e : 0xb1);
      }
      if constexpr (std::is_same_v<T, float>)
        return r;
      else
        return xsimd::bitwise_cast<Batch<T>>(r);
    }
#endif
    using Index = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;
    constexpr auto swap = xsimd::make_batch_constant<Batch<Index>, XorLane<kStride, Index>>();
    return xsimd::swizzle(x, swap);
  }

  // One bit per lane of a mask of floats or doubles, lane 0 in bit 0: the instruction set's own
  // mask move where it has one (xsimd 8.1 has no batch_bool::mask()), else through memory.
  template <class T>
  static unsigned bits(const xsimd::batch_bool<T, A>& m) {
    static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);
    constexpr bool kDouble = std::is_same_v<T, double>;
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
      using Bits = std::conditional_t<kDouble, __mmask8, __mmask16>;
      return static_cast<unsigned>(static_cast<Bits>(m));
    } else if constexpr (std::is_base_of_v<xsimd::avx, A>) {
      if constexpr (kDouble)
        return static_cast<unsigned>(_mm256_movemask_pd(m));
      else
        return static_cast<unsigned>(_mm256_movemask_ps(m));
    } else {
      if constexpr (kDouble)
        return static_cast<unsigned>(_mm_movemask_pd(m));
      else
        return static_cast<unsigned>(_mm_movemask_ps(m));
    }
#else
    constexpr std::size_t kLanes = Batch<T>::size;
    alignas(64) T lanes[kLanes];
    xsimd::select(m, Batch<T>(1), Batch<T>(0)).store_aligned(lanes);
    unsigned result = 0;
    for (std::size_t i = 0; i < kLanes; ++i)
      if (lanes[i] != T(0)) result |= 1u << i;
    return result;
#endif
  }

  struct Iota {
    static constexpr std::uint32_t get(std::size_t i, std::size_t) {
      return static_cast<std::uint32_t>(i);
    }
  };

  static Batch<std::uint32_t> lane_index() {
    return xsimd::make_batch_constant<Batch<std::uint32_t>, Iota>();
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
