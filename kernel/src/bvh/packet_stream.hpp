// The stream's packets, written once over an xsimd architecture A: consecutive rays gathered
// into packets (bvh/packet.hpp) where the query plan finds them coherent, the rest answered one
// at a time by the single-ray walk. Either way hits[i] is intersect(bvh, rays[i]) (occluded
// likewise), bit for bit.
#pragma once

#include <cstddef>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "bvh/bvh_data.hpp"
#include "bvh/line_packet.hpp"
#include "bvh/node.hpp"
#include "bvh/packet.hpp"
#include "bvh/traverse.hpp"
#include "dispatch/query_plan.hpp"
#include "simd/isa_namespace.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class A>
struct PacketStream {
  using Tree = BvhTraversal<A>;
  using Batch = typename Tree::Batch;
  using Packet = PacketWalk<A>;
  using Plan = QueryPlan;
  static constexpr std::size_t kRays = Packet::kRays;
  static constexpr std::size_t kWidth = Packet::kWidth;

  // The tree's box (the union of the root's children), as the packets need it: its bounds
  // (the line packets' sort grid), its largest side (the plan's yardstick for a group's
  // spread) and its largest coordinate magnitude (the rounding margin of bvh/line_packet.hpp).
  // Empty lanes (lo = +inf, hi = -inf) drop out.
  struct TreeSize {
    float lo[3] = {0.0f, 0.0f, 0.0f}, hi[3] = {0.0f, 0.0f, 0.0f};
    float extent = 0.0f, abs = 0.0f;
  };
  static TreeSize tree_size(const BvhData& bvh) {
    const typename Packet::Node root(bvh.nodes, 0, kWidth);
    TreeSize size;
    for (int axis = 0; axis < 3; ++axis) {
      float lo = __builtin_inff(), hi = -__builtin_inff();
      for (std::size_t k = 0; k < kWidth; ++k) {
        lo = root.lo(axis, k) < lo ? root.lo(axis, k) : lo;
        hi = root.hi(axis, k) > hi ? root.hi(axis, k) : hi;
      }
      if (!(lo <= hi)) continue;
      size.lo[axis] = lo;
      size.hi[axis] = hi;
      size.extent = hi - lo > size.extent ? hi - lo : size.extent;
      const float m =
          __builtin_fabsf(lo) > __builtin_fabsf(hi) ? __builtin_fabsf(lo) : __builtin_fabsf(hi);
      size.abs = m > size.abs ? m : size.abs;
    }
    return size;
  }

  // The rays at positions index[0, n) of rays, sharing a direction from scattered origins, as
  // line packets (bvh/line_packet.hpp): trace(p, iv, frame) traces each packet, single(i) each
  // ray that goes alone, store(p, r, i) the packet's ray r back to ray i.
  template <class Rays, class Trace, class Single, class Store>
  static void lines(const Rays& rays, const std::uint16_t* index, std::size_t n,
                    const TreeSize& tree, Trace&& trace, Single&& single, Store&& store) {
    using Line = LinePacket<A>;
    typename Line::Lines l;
    const std::uint16_t* order = Line::prepare(rays, index, n, tree.lo, tree.hi, l, single);
    const float limit = Plan::kLineSpan * tree.extent;
    typename Packet::Rays p;
    typename Line::Slid g;
    typename Line::ShiftedFrame frame;
    std::uint16_t members[kRays];
    for (std::size_t begin = 0; begin < l.count; begin += kRays) {
      std::size_t count = l.count - begin > kRays ? kRays : l.count - begin;
      const std::uint16_t* group = order + begin;
      if (count >= Plan::kPacketMinRays) {
        Line::fill(rays, l, group, count, tree.abs, p, g, members, single);
        if (p.count >= Plan::kPacketMinRays && Line::tight(l, g, p.count, limit)) {
          const typename Packet::Interval iv = Line::interval(l, g, p, frame);
          trace(p, iv, frame);
          for (std::size_t r = 0; r < p.count; ++r)
            store(p, r, members[r]);
          continue;
        }
        group = members;  // the rays fill() did not answer
        count = p.count;
      }
      for (std::size_t r = 0; r < count; ++r)
        single(group[r]);
    }
  }

  // Whether rays[0, n) (n <= kRays, a group the plan finds coherent) go as a packet, and if so
  // gathers into p those that may join it, their positions in index. single(i) answers each of
  // the others: rays the contract says miss, rays not ahead, rays of another octant than the
  // first, or all of them if too few remain.
  template <class Rays, class Single>
  static bool gather(const Rays& rays, std::size_t n, typename Packet::Rays& p,
                     std::uint16_t* index, Single&& single) {
    p.count = 0;
    unsigned first_octant = 8;
    for (std::size_t i = 0; i < n; ++i) {
      const auto& ray = rays[i];
      typename Batch::RaySetup s;
      if (!Batch::setup(ray, s) || !Plan::ahead(ray)) {
        single(i);
        continue;
      }
      const unsigned o = LinePacket<A>::octant(ray.dir);
      if (first_octant == 8) first_octant = o;
      if (o != first_octant) {
        single(i);
        continue;
      }
      index[p.count] = static_cast<std::uint16_t>(i);
      Packet::add(p, ray, s, ray.tmax);
    }
    if (p.count >= Plan::kPacketMinRays) {
      Packet::pad(p);
      return true;
    }
    for (std::size_t r = 0; r < p.count; ++r)
      single(index[r]);
    return false;
  }

  // One window, rays[0, n) with n <= kWindow: groups of kRays consecutive rays that the plan
  // finds coherent go as packets (Packet::interval over their own origins); the rays of the
  // other groups, if the plan finds them parallel, as line packets sorted over the window,
  // else one at a time. trace(p, iv, frame), single(i) and store(p, r, i) as for lines.
  static constexpr std::size_t kWindow = Plan::kLineWindow;
  template <class Rays, class Trace, class Single, class Store>
  static void window(const BvhData& bvh, const Rays& rays, std::size_t n, Trace&& trace,
                     Single&& single, Store&& store) {
    const TreeSize tree = tree_size(bvh);
    typename Packet::Rays p;
    std::uint16_t index[kRays];
    std::uint16_t rest[kWindow];
    std::size_t rest_count = 0;
    for (std::size_t begin = 0; begin < n; begin += kRays) {
      const std::size_t count = n - begin > kRays ? kRays : n - begin;
      if (!Plan::coherent(rays + begin, count, tree.extent)) {
        for (std::size_t i = begin; i < begin + count; ++i)
          rest[rest_count++] = static_cast<std::uint16_t>(i);
        continue;
      }
      const auto one = [&](std::size_t i) { single(begin + i); };
      if (!gather(rays + begin, count, p, index, one)) continue;
      trace(p, Packet::interval(p), typename Packet::OwnFrame{});
      for (std::size_t r = 0; r < p.count; ++r)
        store(p, r, begin + index[r]);
    }
    if (rest_count >= Plan::kPacketRays && Plan::lines(rays, rest, rest_count)) {
      lines(rays, rest, rest_count, tree, trace, single, store);
    } else {
      for (std::size_t j = 0; j < rest_count; ++j)
        single(rest[j]);
    }
  }

  // hits[i] = intersect(bvh, rays[i]), packets where the plan takes them. Rays and Hits as for
  // TreeStream (bvh/stream.hpp).
  template <bool kBranchFree, bool kMasked, class Rays, class Hits>
  static void intersect(const BvhData& bvh, Rays rays, Hits hits, std::size_t n) {
    for (std::size_t begin = 0; begin < n; begin += kWindow) {
      const Rays r0 = rays + begin;
      const Hits h0 = hits + begin;
      window(
          bvh, r0, n - begin > kWindow ? kWindow : n - begin,
          [&](typename Packet::Rays& p, const typename Packet::Interval& iv, const auto& frame) {
            Packet::template intersect<kBranchFree, kMasked>(bvh, p, iv, frame);
          },
          [&](std::size_t i) {
            h0[i] = Tree::template intersect<kBranchFree, kMasked>(bvh, r0[i]);
          },
          [&](const typename Packet::Rays& p, std::size_t r, std::size_t i) {
            h0[i] = {p.best[r], p.best_id[r]};
          });
    }
  }

  // blocked[i] = occluded(bvh, rays[i]), packets where the plan takes them.
  template <bool kMasked, class Rays>
  static void occluded(const BvhData& bvh, Rays rays, bool* blocked, std::size_t n) {
    for (std::size_t begin = 0; begin < n; begin += kWindow) {
      const Rays r0 = rays + begin;
      bool* b0 = blocked + begin;
      window(
          bvh, r0, n - begin > kWindow ? kWindow : n - begin,
          [&](typename Packet::Rays& p, const typename Packet::Interval& iv, const auto& frame) {
            Packet::template occluded<kMasked>(bvh, p, iv, frame);
          },
          [&](std::size_t i) { b0[i] = Tree::template occluded<kMasked>(bvh, r0[i]); },
          [&](const typename Packet::Rays& p, std::size_t r, std::size_t i) {
            b0[i] = p.best[r] == -__builtin_inff();
          });
    }
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
