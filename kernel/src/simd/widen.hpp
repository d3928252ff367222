// A batch of floats as two batches of doubles (its low lanes, then its high ones) and back:
// the surface maths (surface/surface_lanes.hpp) works in double where float would round the
// normal or the front-face test too coarsely; a double tree reads its float boxes widened.
// Conversions are exact one way and round to nearest the other, as static_cast does, so every
// instruction set gives the scalar code's bits.
//
// xsimd 8.1 converts between float and double batches of one architecture only lane by lane
// through memory; the x86 instruction sets have one instruction per half, used here. Other
// architectures take that memory path. Class template over A, like everything the per-ISA
// units include.
#pragma once

#include <array>
#include <cstddef>
#include <type_traits>

#include <xsimd/xsimd.hpp>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct Widen {
  using Floats = xsimd::batch<float, A>;
  using Doubles = xsimd::batch<double, A>;
  static_assert(Floats::size == 2 * Doubles::size);

  struct Halves {
    Doubles low, high;
  };

  SPHRAY_FORCE_INLINE static Halves widen(const Floats& x) {
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
      const __m512d bits = _mm512_castps_pd(x);
      return {_mm512_cvtps_pd(_mm512_castps512_ps256(x)),
              _mm512_cvtps_pd(_mm256_castpd_ps(_mm512_extractf64x4_pd(bits, 1)))};
    } else if constexpr (std::is_base_of_v<xsimd::avx, A>) {
      return {_mm256_cvtps_pd(_mm256_castps256_ps128(x)),
              _mm256_cvtps_pd(_mm256_extractf128_ps(x, 1))};
    } else if constexpr (std::is_base_of_v<xsimd::sse2, A>) {
      return {_mm_cvtps_pd(x), _mm_cvtps_pd(_mm_movehl_ps(x, x))};
    }
#endif
    alignas(A::alignment()) std::array<float, Floats::size> lanes;
    x.store_aligned(lanes.data());
    alignas(A::alignment()) std::array<double, Floats::size> wide;
    for (std::size_t i = 0; i < lanes.size(); ++i)
      wide[i] = lanes[i];
    return {Doubles::load_aligned(wide.data()), Doubles::load_aligned(wide.data() + Doubles::size)};
  }

  // Doubles::size floats from p (any alignment), each widened: a row of a double tree's float
  // box planes (bvh/box_test.hpp).
  SPHRAY_FORCE_INLINE static Doubles load_widened(const float* p) {
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
      return _mm512_cvtps_pd(_mm256_loadu_ps(p));
    } else if constexpr (std::is_base_of_v<xsimd::avx, A>) {
      return _mm256_cvtps_pd(_mm_loadu_ps(p));
    } else if constexpr (std::is_base_of_v<xsimd::sse2, A>) {
      return _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))));
    }
#endif
    alignas(A::alignment()) std::array<double, Doubles::size> wide;
    for (std::size_t i = 0; i < wide.size(); ++i)
      wide[i] = p[i];
    return Doubles::load_aligned(wide.data());
  }

  SPHRAY_FORCE_INLINE static Floats narrow(const Doubles& low, const Doubles& high) {
#if defined(__x86_64__) || defined(__i386__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
      const __m512d joined =
          _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_castps_pd(_mm512_cvtpd_ps(low))),
                             _mm256_castps_pd(_mm512_cvtpd_ps(high)), 1);
      return _mm512_castpd_ps(joined);
    } else if constexpr (std::is_base_of_v<xsimd::avx, A>) {
      return _mm256_set_m128(_mm256_cvtpd_ps(high), _mm256_cvtpd_ps(low));
    } else if constexpr (std::is_base_of_v<xsimd::sse2, A>) {
      return _mm_movelh_ps(_mm_cvtpd_ps(low), _mm_cvtpd_ps(high));
    }
#endif
    alignas(A::alignment()) std::array<double, Floats::size> wide;
    low.store_aligned(wide.data());
    high.store_aligned(wide.data() + Doubles::size);
    alignas(A::alignment()) std::array<float, Floats::size> lanes;
    for (std::size_t i = 0; i < lanes.size(); ++i)
      lanes[i] = static_cast<float>(wide[i]);
    return Floats::load_aligned(lanes.data());
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
