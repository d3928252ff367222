// Horizontal reductions across the lanes of one xsimd batch, once per ray (xsimd 8.1 has no
// reduce_min). Class templates over A, like everything the per-ISA units instantiate.
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

namespace sphray::detail {

template <class A>
struct LaneReduce {
  template <class T>
  using Batch = xsimd::batch<T, A>;
  static constexpr std::size_t kWidth = Batch<float>::size;

  // The lane index i ^ kStride: swapping halves, then quarters, ... of the batch.
  template <std::size_t kStride>
  struct XorLane {
    static constexpr std::uint32_t get(std::size_t i, std::size_t) {
      return static_cast<std::uint32_t>(i ^ kStride);
    }
  };

  // Every lane gets the minimum over all lanes: log2(width) swizzle-and-min steps, no branch.
  template <class T, std::size_t kStride = kWidth / 2>
  static Batch<T> all_min(Batch<T> x) {
    if constexpr (kStride == 0) {
      return x;
    } else {
      constexpr auto swap = xsimd::make_batch_constant<Batch<std::uint32_t>, XorLane<kStride>>();
      return all_min<T, kStride / 2>(xsimd::min(x, xsimd::swizzle(x, swap)));
    }
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

}  // namespace sphray::detail
