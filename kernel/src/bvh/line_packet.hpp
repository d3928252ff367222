// Packets of near-parallel rays from scattered origins (shadow rays towards one light from a
// frame's hit points), written once over an xsimd architecture A.
//
// For rays that share a direction, what decides which boxes they meet is their line, not where
// on it they start: two rays whose lines are close follow nearly the same path whatever their
// depth. So each ray's origin is slid along its own direction onto one plane across the chunk's
// main axis (the one the first ray's direction is largest on), behind every origin: the
// virtual origin q = o + s d with s <= 0, and the ray's t becomes t - s (its shift). The
// chunk's rays are then sorted by a Morton key of q in that plane (a stable radix sort of an
// index permutation, on the stack), and consecutive rays of that order form packets whose
// interval ray (bvh/packet.hpp) has the origin box of their q's: flat across the main axis,
// as narrow as their lines are close, however far apart the hit points lie in depth.
//
// Every ray still takes its own exact leaf-box and leaf tests; only the inner-node test uses
// the virtual origins, and it must stay conservative: reject a box only if every ray's own
// rounded test would. The slide is rounded, and the rays' own tests accept boxes their exact
// lines miss by a relative few ulps of the distances, all below kMarginScale (2^-16) of M, the
// largest coordinate magnitude of the tree's box, the origins and the q's (every distance the
// walk computes is at most a few M, and its rounding a few ulps of it): the interval's origin
// box is widened by margin = M * kMarginScale on every side (which is the node's boxes widened
// by as much), and its tmin and best bounds by margin over the smallest direction component on
// the main axis (a t error of margin / |d_k| at most). The results are therefore each ray's
// single-ray answer, bit for bit, as for the other packets.
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "bvh/bvh_data.hpp"
#include "bvh/node.hpp"
#include "bvh/packet.hpp"
#include "dispatch/query_plan.hpp"
#include "simd/isa_namespace.hpp"
#include "simd/lane_reduce.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct LinePacket {
  using Packet = PacketWalk<A>;
  using Batch = typename Packet::Batch;
  using Floats = typename Packet::Floats;
  using Interval = typename Packet::Interval;
  using Plan = QueryPlan;
  static constexpr std::size_t kRays = Packet::kRays;
  static constexpr std::size_t kWidth = Packet::kWidth;
  static constexpr std::size_t kChunk = Plan::kStreamChunk;
  static_assert(kChunk <= 65536, "positions fit 16 bits");
  static constexpr float kMarginScale = 0x1p-16f;
  // Per axis of the plane: a 256 x 256 grid over the chunk's lines, far finer than a packet's
  // span (QueryPlan::kLineSpan), and a 16-bit key: two radix passes.
  static constexpr unsigned kKeyBits = 8;

  // The chunk's rays slid onto the plane, by their position in the chunk.
  struct Lines {
    alignas(64) float q[3][kChunk];
    alignas(64) float shift[kChunk];  // -s >= 0: t on the virtual ray minus t on the ray
    std::uint16_t order[2][kChunk];   // the rays that may join packets, then sorted
    std::uint16_t key[2][kChunk];
    std::size_t count;  // of order
    unsigned axis;      // the main axis, across which the plane lies
    float margin;
  };

  // The packet's t bound: the largest best + shift, widened by margin_t (and a relative 2^-20,
  // for the rounding of the sum); -inf when every ray is done.
  struct ShiftedFrame {
    alignas(64) float shift[kRays];
    float margin_t = 0.0f;
    float max_best(const typename Packet::Rays& p) const {
      Floats m = Floats::load_aligned(p.best) + Floats::load_aligned(shift);
      for (std::size_t r = kWidth; r < kRays; r += kWidth)
        m = xsimd::max(m, Floats::load_aligned(p.best + r) + Floats::load_aligned(shift + r));
      const float best = -LaneReduce<A>::template all_min<float>(-m).get(0);
      if (best == -__builtin_inff()) return best;
      return best + (__builtin_fabsf(best) * 0x1p-20f + margin_t);
    }
  };

  static unsigned main_axis(const Vec3& d) {
    const float x = __builtin_fabsf(d.x), y = __builtin_fabsf(d.y), z = __builtin_fabsf(d.z);
    return x >= y && x >= z ? 0u : (y >= z ? 1u : 2u);
  }

  static unsigned octant(const Vec3& d) {
    return (__builtin_signbit(d.x) ? 1u : 0u) | (__builtin_signbit(d.y) ? 2u : 0u) |
           (__builtin_signbit(d.z) ? 4u : 0u);
  }

  // Spreads the low 8 bits of v to every other bit.
  static std::uint32_t spread(std::uint32_t v) {
    v = (v | (v << 4)) & 0x0f0f0f0fu;
    v = (v | (v << 2)) & 0x33333333u;
    v = (v | (v << 1)) & 0x55555555u;
    return v;
  }

  // Slides the rays at positions index[0, n) of rays (n <= kChunk) onto the plane and sorts
  // them, into l. single(i) answers
  // the rays that may not join a packet: those the contract says miss, those not ahead, those of
  // another octant than the first ray that may. tree_abs: the largest coordinate magnitude of
  // the tree's box. Returns where the sorted order is (l.order[which]).
  template <class Single>
  static std::uint16_t* prepare(const Ray* rays, const std::uint16_t* index, std::size_t n,
                                float tree_abs, Lines& l, Single&& single) {
    unsigned first_octant = 8;
    l.count = 0;
    l.axis = 0;
    float plane = 0.0f;
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t i = index[j];
      const Ray& ray = rays[i];
      // What the slide needs (finite origin and direction, a normal main component: ahead);
      // the rest of SphereLanes::setup's checks come when the packet is filled.
      const Vec3 &o = ray.origin, &d = ray.dir;
      const bool finite = o.x - o.x == 0.0f && o.y - o.y == 0.0f && o.z - o.z == 0.0f &&
                          d.x - d.x == 0.0f && d.y - d.y == 0.0f && d.z - d.z == 0.0f;
      if (!finite || !Plan::ahead(ray)) {
        single(i);
        continue;
      }
      const unsigned side = octant(d);
      if (first_octant == 8) {
        first_octant = side;
        l.axis = main_axis(ray.dir);
        plane = ray.origin[static_cast<int>(l.axis)];
      }
      if (side != first_octant) {
        single(i);
        continue;
      }
      l.order[0][l.count++] = static_cast<std::uint16_t>(i);
      // Behind every origin: the lowest for a positive direction, the highest for a negative.
      const float c = ray.origin[static_cast<int>(l.axis)];
      plane =
          (first_octant >> l.axis & 1u) == 0 ? (c < plane ? c : plane) : (c > plane ? c : plane);
    }
    if (l.count == 0) return l.order[0];
    const int k = static_cast<int>(l.axis), a = (k + 1) % 3, b = (k + 2) % 3;
    float abs_max = tree_abs, lo_a = __builtin_inff(), hi_a = -lo_a, lo_b = lo_a, hi_b = hi_a;
    const auto grow = [&](float v) {
      abs_max = __builtin_fabsf(v) > abs_max ? __builtin_fabsf(v) : abs_max;
    };
    for (std::size_t j = 0; j < l.count; ++j) {
      const std::size_t i = l.order[0][j];
      const Vec3 &o = rays[i].origin, &d = rays[i].dir;
      const float s = (plane - o[k]) / d[k];  // <= 0
      l.shift[i] = -s;
      l.q[k][i] = plane;
      l.q[a][i] = o[a] + s * d[a];
      l.q[b][i] = o[b] + s * d[b];
      grow(o.x), grow(o.y), grow(o.z), grow(l.q[a][i]), grow(l.q[b][i]);
      lo_a = l.q[a][i] < lo_a ? l.q[a][i] : lo_a;
      hi_a = l.q[a][i] > hi_a ? l.q[a][i] : hi_a;
      lo_b = l.q[b][i] < lo_b ? l.q[b][i] : lo_b;
      hi_b = l.q[b][i] > hi_b ? l.q[b][i] : hi_b;
    }
    // 0x1p-100f keeps the margin positive in a scene of points at 0.
    l.margin = abs_max * kMarginScale + 0x1p-100f;
    // The Morton key of q on a grid over the q's bounds; the sort keeps the rays' order
    // within a cell.
    constexpr float kCells = static_cast<float>(1u << kKeyBits);
    const float scale_a = hi_a > lo_a ? (kCells - 1.0f) / (hi_a - lo_a) : 0.0f;
    const float scale_b = hi_b > lo_b ? (kCells - 1.0f) / (hi_b - lo_b) : 0.0f;
    for (std::size_t j = 0; j < l.count; ++j) {
      const std::size_t i = l.order[0][j];
      const auto ca = static_cast<std::uint32_t>((l.q[a][i] - lo_a) * scale_a);
      const auto cb = static_cast<std::uint32_t>((l.q[b][i] - lo_b) * scale_b);
      constexpr std::uint32_t kLast = (1u << kKeyBits) - 1u;
      l.key[0][j] = static_cast<std::uint16_t>(spread(ca < kLast ? ca : kLast) |
                                               spread(cb < kLast ? cb : kLast) << 1);
    }
    return sort(l);
  }

  // A stable radix sort of l.order by l.key, 8 bits a pass.
  static std::uint16_t* sort(Lines& l) {
    constexpr unsigned kBits = 8, kPasses = (2 * kKeyBits + kBits - 1) / kBits;
    unsigned from = 0;
    for (unsigned pass = 0; pass < kPasses; ++pass, from ^= 1u) {
      std::uint32_t count[1u << kBits] = {};
      const unsigned shift = pass * kBits;
      const std::uint16_t* key = l.key[from];
      for (std::size_t j = 0; j < l.count; ++j)
        ++count[key[j] >> shift & ((1u << kBits) - 1u)];
      std::uint32_t sum = 0;
      for (std::uint32_t& c : count) {
        const std::uint32_t here = c;
        c = sum;
        sum += here;
      }
      for (std::size_t j = 0; j < l.count; ++j) {
        const std::uint32_t to = count[key[j] >> shift & ((1u << kBits) - 1u)]++;
        l.key[from ^ 1u][to] = key[j];
        l.order[from ^ 1u][to] = l.order[from][j];
      }
    }
    return l.order[from];
  }

  // Whether the rays at positions group[0, n) of the chunk have lines close enough for a
  // packet: their q's span at most limit across the main axis.
  static bool tight(const Lines& l, const std::uint16_t* group, std::size_t n, float limit) {
    const unsigned a = (l.axis + 1) % 3, b = (l.axis + 2) % 3;
    float lo_a = l.q[a][group[0]], hi_a = lo_a, lo_b = l.q[b][group[0]], hi_b = lo_b;
    for (std::size_t r = 1; r < n; ++r) {
      const float qa = l.q[a][group[r]], qb = l.q[b][group[r]];
      lo_a = qa < lo_a ? qa : lo_a;
      hi_a = qa > hi_a ? qa : hi_a;
      lo_b = qb < lo_b ? qb : lo_b;
      hi_b = qb > hi_b ? qb : hi_b;
    }
    return hi_a - lo_a <= limit && hi_b - lo_b <= limit;
  }

  // The interval ray of the packet p of the rays at positions group[0, p.count), in the frame
  // of their virtual origins, widened by the margin; frame gets their shifts.
  static Interval interval(const Lines& l, const std::uint16_t* group,
                           const typename Packet::Rays& p, ShiftedFrame& frame) {
    const float* inv[3] = {p.inv_dx, p.inv_dy, p.inv_dz};
    Interval iv;
    float tmin = __builtin_inff();
    for (std::size_t r = 0; r < p.count; ++r) {
      const float t = p.tmin[r] + l.shift[group[r]];
      tmin = t < tmin ? t : tmin;
      frame.shift[r] = l.shift[group[r]];
    }
    for (std::size_t r = p.count; r < kRays; ++r)
      frame.shift[r] = 0.0f;  // padding: best -inf stays -inf
    for (int axis = 0; axis < 3; ++axis) {
      float o_lo = l.q[axis][group[0]], o_hi = o_lo, i_lo = inv[axis][0], i_hi = i_lo;
      for (std::size_t r = 1; r < p.count; ++r) {
        const float q = l.q[axis][group[r]];
        o_lo = q < o_lo ? q : o_lo;
        o_hi = q > o_hi ? q : o_hi;
        i_lo = inv[axis][r] < i_lo ? inv[axis][r] : i_lo;
        i_hi = inv[axis][r] > i_hi ? inv[axis][r] : i_hi;
      }
      o_lo -= l.margin;
      o_hi += l.margin;
      const bool negative = i_hi < 0.0f;  // one octant: every inverse has this sign
      iv.near_o[axis] = Floats(negative ? o_lo : o_hi);
      iv.far_o[axis] = Floats(negative ? o_hi : o_lo);
      iv.inv_lo[axis] = Floats(i_lo);
      iv.inv_hi[axis] = Floats(i_hi);
      iv.near_row[axis] = 2 * static_cast<std::size_t>(axis) + (negative ? 1u : 0u);
      if (static_cast<unsigned>(axis) == l.axis) {
        // t moves by margin / |d_k| at most for a move of margin along the main axis.
        const float inv_max = __builtin_fabsf(i_lo) > __builtin_fabsf(i_hi) ? __builtin_fabsf(i_lo)
                                                                            : __builtin_fabsf(i_hi);
        frame.margin_t = l.margin * inv_max * 2.0f;
      }
    }
    tmin -= __builtin_fabsf(tmin) * 0x1p-20f + frame.margin_t;
    iv.tmin = Floats(tmin > 0.0f ? tmin : 0.0f);
    return iv;
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
