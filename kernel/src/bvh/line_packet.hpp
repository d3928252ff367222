// Packets of near-parallel rays from scattered origins (shadow rays towards one light from a
// frame's hit points), written once over an xsimd architecture A.
//
// For rays that share a direction, what decides which boxes they meet is their line, not where
// on it they start: two rays whose lines are close follow nearly the same path whatever their
// depth. So the window's rays (QueryPlan::kLineWindow) are sorted by a Morton key of where
// their lines cross a plane across the main axis (the one the first ray's direction is
// largest on), on a grid over the tree's box seen along that direction (a stable radix sort of
// an index permutation, on the stack), and each packet of consecutive rays of that order has
// its origins slid along their own directions onto one plane behind every origin of the
// window: the virtual origin q = o + s d with s <= 0, and the ray's t becomes t - s (its
// shift). The packet's interval ray (bvh/packet.hpp) has the origin box of their q's: flat
// across the main axis, as narrow as their lines are close, however far apart the hit points
// lie in depth.
//
// Every ray still takes its own exact leaf-box and leaf tests; only the inner-node test uses
// the virtual origins, and it must stay conservative: reject a box only if every ray's own
// rounded test would. The slide is rounded, and the rays' own tests accept boxes their exact
// lines miss by a relative few ulps of the distances, all below kMarginScale (2^-16) of M, the
// largest coordinate magnitude of the tree's box, the packet's origins and its q's (every
// distance the walk computes is at most a few M, and its rounding a few ulps of it): the
// interval's origin box is widened by margin = M * kMarginScale on every side (which is the
// node's boxes widened by as much), and its tmin and best bounds by margin over the smallest
// direction component on the main axis (a t error of margin / |d_k| at most). The results are
// therefore each ray's single-ray answer, bit for bit, as for the other packets.
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
  using Mask = typename Packet::Mask;
  using Plan = QueryPlan;
  static constexpr std::size_t kRays = Packet::kRays;
  static constexpr std::size_t kWidth = Packet::kWidth;
  static constexpr std::size_t kWindow = Plan::kLineWindow;
  static_assert(kWindow <= 65536, "positions fit 16 bits");
  static constexpr float kMarginScale = 0x1p-16f;
  // Per axis of the plane: a 256 x 256 grid over the window's lines, far finer than a packet's
  // span (QueryPlan::kLineSpan), and a 16-bit key: two radix passes.
  static constexpr unsigned kKeyBits = 8;

  // The window's rays that may join packets, sorted by their lines: 8 bytes a ray, so that a
  // window of kWindow rays sorts on the stack. Where a ray's line crosses the plane is not
  // kept: fill() slides each packet's rays again, a batch at a time.
  struct Lines {
    std::uint16_t order[2][kWindow];  // positions of the rays that may join packets, then sorted
    std::uint16_t key[2][kWindow];
    std::size_t count;  // of order
    unsigned axis;      // the main axis, across which the plane lies
    float plane;        // the plane's coordinate on it, behind every origin
  };

  // A packet's rays slid onto the plane, by their place in the packet, and the margin of its
  // interval ray.
  struct Slid {
    alignas(64) float q[3][kRays];
    alignas(64) float shift[kRays];  // -s >= 0: t on the virtual ray minus t on the ray
    float margin;
  };

  // The grid of the sort's keys: where the lines of direction d cross the plane across axis k
  // at plane, 256 x 256 cells over the bounds of the tree's box [lo, hi] seen along d, which
  // hold every line that meets the tree (prepare() gives the others the last key).
  struct Grid {
    unsigned k, a, b;
    float plane, lo_a, lo_b, scale_a, scale_b;
    Vec3 d;

    Grid(unsigned axis, float at, const Vec3& dir, const float* lo, const float* hi)
        : k(axis), a((axis + 1) % 3), b((axis + 2) % 3), plane(at), d(dir) {
      float min_a = __builtin_inff(), max_a = -min_a, min_b = min_a, max_b = max_a;
      for (unsigned corner = 0; corner < 8; ++corner) {
        const Vec3 c{(corner & 1u) ? hi[0] : lo[0], (corner & 2u) ? hi[1] : lo[1],
                     (corner & 4u) ? hi[2] : lo[2]};
        float qa, qb;
        cross(c, qa, qb);
        min_a = qa < min_a ? qa : min_a;
        max_a = qa > max_a ? qa : max_a;
        min_b = qb < min_b ? qb : min_b;
        max_b = qb > max_b ? qb : max_b;
      }
      constexpr float kLast = static_cast<float>((1u << kKeyBits) - 1u);
      lo_a = min_a, lo_b = min_b;
      scale_a = max_a > min_a ? kLast / (max_a - min_a) : 0.0f;
      scale_b = max_b > min_b ? kLast / (max_b - min_b) : 0.0f;
    }

    // Where the line through p along d crosses the plane.
    void cross(const Vec3& p, float& qa, float& qb) const {
      const float s = (plane - p[static_cast<int>(k)]) / d[static_cast<int>(k)];
      qa = p[static_cast<int>(a)] + s * d[static_cast<int>(a)];
      qb = p[static_cast<int>(b)] + s * d[static_cast<int>(b)];
    }

    // The Morton keys of the cells of the rows' lines through their origins, into keys; the
    // lanes whose lines cross the grid (NaN does not) as bits.
    template <class R>
    unsigned keys(const R& rows, std::int32_t* keys) const {
      using Ints = xsimd::batch<std::int32_t, A>;
      const Floats dk(d[static_cast<int>(k)]), da(d[static_cast<int>(a)]),
          db(d[static_cast<int>(b)]);
      const Floats s = (Floats(plane) - Floats::load_aligned(rows.o[k])) / dk;
      const Floats ca = (Floats::load_aligned(rows.o[a]) + s * da - Floats(lo_a)) * Floats(scale_a);
      const Floats cb = (Floats::load_aligned(rows.o[b]) + s * db - Floats(lo_b)) * Floats(scale_b);
      const Floats zero(0.0f), last(static_cast<float>((1u << kKeyBits) - 1u));
      const Mask inside = (ca >= zero) & (ca <= last) & (cb >= zero) & (cb <= last);
      const Ints ia = xsimd::batch_cast<std::int32_t>(xsimd::select(inside, ca, zero));
      const Ints ib = xsimd::batch_cast<std::int32_t>(xsimd::select(inside, cb, zero));
      (spread(ia) | (spread(ib) << 1)).store_aligned(keys);
      return LaneReduce<A>::bits(inside);
    }
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

  // Spreads the low 8 bits of each lane of v (at most 255) to every other bit.
  static xsimd::batch<std::int32_t, A> spread(xsimd::batch<std::int32_t, A> v) {
    using Ints = xsimd::batch<std::int32_t, A>;
    v = (v | (v << 4)) & Ints(0x0f0f0f0f);
    v = (v | (v << 2)) & Ints(0x33333333);
    v = (v | (v << 1)) & Ints(0x55555555);
    return v;
  }

  // Sorts the rays at positions index[0, n) of rays (n <= kWindow) by their lines, into l, in
  // one pass over them, a batch at a time: the key of each is its cell on a grid over the
  // tree's box [lo, hi] seen along the first usable ray's direction, on the plane through
  // that ray's origin (the sort needs no particular plane; the packets slide onto l.plane,
  // behind every origin). single(i) answers the rays that may not join a packet: those not
  // usable(), those of another octant than the first usable one (SphereLanes::setup's other
  // checks come in fill()). Returns where the sorted order is (l.order[which]).
  template <class Rays, class Single>  // Rays: `const Ray*` or RayColumns, as in bvh/stream.hpp
  static std::uint16_t* prepare(const Rays& rays, const std::uint16_t* index, std::size_t n,
                                const float* lo, const float* hi, Lines& l, Single&& single) {
    l.count = 0;
    std::size_t j = 0;
    while (j < n && !usable(rays[index[j]]))
      single(index[j++]);
    if (j == n) return l.order[0];
    const Ray first = rays[index[j]];
    l.axis = main_axis(first.dir);
    l.plane = first.origin[static_cast<int>(l.axis)];
    const Grid grid(l.axis, l.plane, first.dir, lo, hi);
    const bool positive = !__builtin_signbit(first.dir[static_cast<int>(l.axis)]);
    Rows rows;
    Floats plane(l.plane);
    for (; j < n; j += kWidth) {
      const std::size_t m = n - j < kWidth ? n - j : kWidth;
      rows.load(rays, index + j, m);
      const Mask take = rows.usable() & rows.in_octant(first.dir);
      // Behind every origin: the lowest for a positive direction, the highest for a negative.
      const Floats c = Floats::load_aligned(rows.o[l.axis]);
      plane = positive ? xsimd::min(xsimd::select(take, c, plane), plane)
                       : xsimd::max(xsimd::select(take, c, plane), plane);
      alignas(64) std::int32_t keys[kWidth];
      const unsigned inside = grid.keys(rows, keys);
      const unsigned taken = LaneReduce<A>::bits(take);
      for (std::size_t r = 0; r < m; ++r) {
        if ((taken >> r & 1u) == 0) {
          single(index[j + r]);
          continue;
        }
        // Lines that miss the grid (and so the tree) all take the last key: sorted after the
        // others, they do not widen their packets.
        l.key[0][l.count] =
            (inside >> r & 1u) != 0 ? static_cast<std::uint16_t>(keys[r]) : std::uint16_t{0xffff};
        l.order[0][l.count++] = index[j + r];
      }
    }
    const float behind = positive ? LaneReduce<A>::template all_min<float>(plane).get(0)
                                  : -LaneReduce<A>::template all_min<float>(-plane).get(0);
    l.plane = behind;
    return sort(l);
  }

  // A batch of rays as rows of their fields, one ray per lane.
  struct Rows {
    alignas(64) float o[3][kWidth];
    alignas(64) float d[3][kWidth];
    alignas(64) float tmin[kWidth];

    // The rays at positions at[0, m) (m <= kWidth), then copies of the first.
    template <class Rays>
    void load(const Rays& rays, const std::uint16_t* at, std::size_t m) {
      for (std::size_t r = 0; r < kWidth; ++r) {
        const auto& ray = rays[at[r < m ? r : 0]];
        o[0][r] = ray.origin.x, o[1][r] = ray.origin.y, o[2][r] = ray.origin.z;
        d[0][r] = ray.dir.x, d[1][r] = ray.dir.y, d[2][r] = ray.dir.z;
        tmin[r] = ray.tmin;
      }
    }

    // usable(ray) in each lane.
    Mask usable() const {
      const Floats zero(0.0f), normal(0x1p-126f);
      Mask ok = Floats::load_aligned(tmin) >= zero;
      for (unsigned axis = 0; axis < 3; ++axis) {
        const Floats x = Floats::load_aligned(o[axis]), v = Floats::load_aligned(d[axis]);
        ok = ok & (x - x == zero) & (v - v == zero) & (xsimd::abs(v) >= normal);
      }
      return ok;
    }

    // The lanes whose direction has the signs of dir's: for usable rays (no zero component),
    // octant(d) == octant(dir).
    Mask in_octant(const Vec3& dir) const {
      Mask same(true);
      for (unsigned axis = 0; axis < 3; ++axis) {
        const Mask negative = Floats::load_aligned(d[axis]) < Floats(0.0f);
        same = same & (__builtin_signbit(dir[static_cast<int>(axis)]) ? negative : !negative);
      }
      return same;
    }
  };

  // What the slide needs: a finite origin and direction, and a normal main component (ahead).
  static bool usable(const Ray& ray) {
    const Vec3 &o = ray.origin, &d = ray.dir;
    return o.x - o.x == 0.0f && o.y - o.y == 0.0f && o.z - o.z == 0.0f && d.x - d.x == 0.0f &&
           d.y - d.y == 0.0f && d.z - d.z == 0.0f && Plan::ahead(ray);
  }

  // Fills p with the rays at places group[0, n) of the window (n <= kRays) that the contract
  // lets hit, their places in the window in members, their slides onto l's plane in g and
  // the margin of their interval; the others go to single(i). What SphereLanes::setup and
  // PacketWalk::add compute ray by ray is computed here a batch of rays at a time, with the
  // same operations in every lane: the same bits. Slots past p.count are padding (pad()).
  template <class Rays, class Single>
  static void fill(const Rays& rays, const Lines& l, const std::uint16_t* group, std::size_t n,
                   float tree_abs, typename Packet::Rays& p, Slid& g, std::uint16_t* members,
                   Single&& single) {
    std::uint64_t valid = 0;
    for (std::size_t r = 0; r < kRays; ++r) {
      const auto& ray = rays[group[r < n ? r : 0]];  // past n: a copy of the first, not counted
      p.ox[r] = ray.origin.x, p.oy[r] = ray.origin.y, p.oz[r] = ray.origin.z;
      p.dx[r] = ray.dir.x, p.dy[r] = ray.dir.y, p.dz[r] = ray.dir.z;
      p.tmin[r] = ray.tmin, p.tmax[r] = ray.tmax, p.mask[r] = ray.mask;
      valid |= static_cast<std::uint64_t>(r < n && ray.mask != 0) << r;
    }
    float* o[3] = {p.ox, p.oy, p.oz};
    float* d[3] = {p.dx, p.dy, p.dz};
    float* inv[3] = {p.inv_dx, p.inv_dy, p.inv_dz};
    const unsigned k = l.axis, a = (k + 1) % 3, b = (k + 2) % 3;
    Floats abs_max(tree_abs);
    for (std::size_t r = 0; r < kRays; r += kWidth) {
      const Floats dx = Floats::load_aligned(p.dx + r), dy = Floats::load_aligned(p.dy + r),
                   dz = Floats::load_aligned(p.dz + r);
      // SphereLanes::setup's a = |d|^2, |d| and 1/a, and its checks (prepare() checked
      // finiteness).
      const Floats len2 = dx * dx + dy * dy + dz * dz;
      const auto ok = (Floats::load_aligned(p.tmin + r) < Floats::load_aligned(p.tmax + r)) &
                      (len2 >= Floats(0x1p-126f)) & (len2 < Floats(__builtin_inff()));
      valid &= ~(static_cast<std::uint64_t>(LaneReduce<A>::bits(!ok)) << r);
      xsimd::sqrt(len2).store_aligned(p.length + r);
      (Floats(1.0f) / len2).store_aligned(p.inv_a + r);
      for (unsigned axis = 0; axis < 3; ++axis) {
        (Floats(1.0f) / Floats::load_aligned(d[axis] + r)).store_aligned(inv[axis] + r);
        abs_max = xsimd::max(xsimd::abs(Floats::load_aligned(o[axis] + r)), abs_max);
      }
      // The slide: s = (plane - o_k) / d_k <= 0, q = o + s d.
      const Floats s =
          (Floats(l.plane) - Floats::load_aligned(o[k] + r)) / Floats::load_aligned(d[k] + r);
      const Floats qa = Floats::load_aligned(o[a] + r) + s * Floats::load_aligned(d[a] + r);
      const Floats qb = Floats::load_aligned(o[b] + r) + s * Floats::load_aligned(d[b] + r);
      qa.store_aligned(g.q[a] + r);
      qb.store_aligned(g.q[b] + r);
      Floats(l.plane).store_aligned(g.q[k] + r);
      (-s).store_aligned(g.shift + r);
      abs_max = xsimd::max(xsimd::abs(qa), xsimd::max(xsimd::abs(qb), abs_max));
    }
    // 0x1p-100f keeps the margin positive in a scene of points at 0.
    g.margin = -LaneReduce<A>::template all_min<float>(-abs_max).get(0) * kMarginScale + 0x1p-100f;
    p.count = 0;
    for (std::size_t r = 0; r < n; ++r) {
      if ((valid >> r & 1u) == 0) {
        single(group[r]);
        continue;
      }
      if (r != p.count) move(p, g, r, p.count);
      members[p.count++] = group[r];
    }
    for (std::size_t r = 0; r < p.count; ++r) {
      p.best[r] = p.tmax[r];
      p.best_id[r] = kNoHit;
    }
    Packet::pad(p);
  }

  // Moves the ray in slot from of p and g to slot to.
  static void move(typename Packet::Rays& p, Slid& g, std::size_t from, std::size_t to) {
    for (float* v : {p.ox, p.oy, p.oz, p.dx, p.dy, p.dz, p.inv_dx, p.inv_dy, p.inv_dz, p.tmin,
                     p.tmax, p.length, p.inv_a, g.q[0], g.q[1], g.q[2], g.shift})
      v[to] = v[from];
    p.mask[to] = p.mask[from];
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

  // Whether the n rays of g have lines close enough for a packet: their q's span at most
  // limit across the main axis.
  static bool tight(const Lines& l, const Slid& g, std::size_t n, float limit) {
    const float* qa = g.q[(l.axis + 1) % 3];
    const float* qb = g.q[(l.axis + 2) % 3];
    float lo_a = qa[0], hi_a = lo_a, lo_b = qb[0], hi_b = lo_b;
    for (std::size_t r = 1; r < n; ++r) {
      lo_a = qa[r] < lo_a ? qa[r] : lo_a;
      hi_a = qa[r] > hi_a ? qa[r] : hi_a;
      lo_b = qb[r] < lo_b ? qb[r] : lo_b;
      hi_b = qb[r] > hi_b ? qb[r] : hi_b;
    }
    return hi_a - lo_a <= limit && hi_b - lo_b <= limit;
  }

  // The interval ray of the packet p whose rays, slid, are g's first p.count, in the frame of
  // their virtual origins, widened by the margin; frame gets their shifts.
  static Interval interval(const Lines& l, const Slid& g, const typename Packet::Rays& p,
                           ShiftedFrame& frame) {
    const float* inv[3] = {p.inv_dx, p.inv_dy, p.inv_dz};
    Interval iv;
    float tmin = __builtin_inff();
    for (std::size_t r = 0; r < p.count; ++r) {
      const float t = p.tmin[r] + g.shift[r];
      tmin = t < tmin ? t : tmin;
      frame.shift[r] = g.shift[r];
    }
    for (std::size_t r = p.count; r < kRays; ++r)
      frame.shift[r] = 0.0f;  // padding: best -inf stays -inf
    for (int axis = 0; axis < 3; ++axis) {
      float o_lo = g.q[axis][0], o_hi = o_lo, i_lo = inv[axis][0], i_hi = i_lo;
      for (std::size_t r = 1; r < p.count; ++r) {
        const float q = g.q[axis][r];
        o_lo = q < o_lo ? q : o_lo;
        o_hi = q > o_hi ? q : o_hi;
        i_lo = inv[axis][r] < i_lo ? inv[axis][r] : i_lo;
        i_hi = inv[axis][r] > i_hi ? inv[axis][r] : i_hi;
      }
      o_lo -= g.margin;
      o_hi += g.margin;
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
        frame.margin_t = g.margin * inv_max * 2.0f;
      }
    }
    tmin -= __builtin_fabsf(tmin) * 0x1p-20f + frame.margin_t;
    iv.tmin = Floats(tmin > 0.0f ? tmin : 0.0f);
    return iv;
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
