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

  // The largest side of the tree's box (the union of the root's children).
  static float tree_extent(const BvhData& bvh) {
    const typename Packet::Node root(bvh.nodes, 0, kWidth);
    float extent = 0.0f;
    for (int axis = 0; axis < 3; ++axis) {
      float lo = __builtin_inff(), hi = -__builtin_inff();
      for (std::size_t k = 0; k < kWidth; ++k) {
        lo = root.lo(axis, k) < lo ? root.lo(axis, k) : lo;
        hi = root.hi(axis, k) > hi ? root.hi(axis, k) : hi;
      }
      extent = hi - lo > extent ? hi - lo : extent;
    }
    return extent;
  }

  // The largest coordinate magnitude of the tree's box (bvh/line_packet.hpp's margin).
  static float tree_abs(const BvhData& bvh) {
    const typename Packet::Node root(bvh.nodes, 0, kWidth);
    float m = 0.0f;
    for (int axis = 0; axis < 3; ++axis) {
      for (std::size_t k = 0; k < kWidth; ++k) {
        if (!(root.lo(axis, k) <= root.hi(axis, k))) continue;  // an empty lane
        const float lo = __builtin_fabsf(root.lo(axis, k)), hi = __builtin_fabsf(root.hi(axis, k));
        m = lo > m ? lo : m;
        m = hi > m ? hi : m;
      }
    }
    return m;
  }

  // Rays sharing a direction from scattered origins (bvh/line_packet.hpp): run(p, iv, frame)
  // traces each packet, single(i) each ray that goes alone, store(r, i) the packet's ray r
  // back to ray i of the chunk.
  template <class Run, class Single, class Store>
  static void lines(const BvhData& bvh, const Ray* rays, std::size_t n, float extent, Run&& run,
                    Single&& single, Store&& store) {
    using Line = LinePacket<A>;
    typename Line::Lines l;
    const std::uint16_t* order = Line::prepare(rays, n, tree_abs(bvh), l, single);
    const float limit = Plan::kLineSpan * extent;
    typename Packet::Rays p;
    typename Line::ShiftedFrame frame;
    for (std::size_t begin = 0; begin < l.count; begin += kRays) {
      const std::size_t count = l.count - begin > kRays ? kRays : l.count - begin;
      const std::uint16_t* group = order + begin;
      if (count < Plan::kPacketMinRays || !Line::tight(l, group, count, limit)) {
        for (std::size_t r = 0; r < count; ++r)
          single(group[r]);
        continue;
      }
      // The rays the contract says miss (prepare checked only what the slide needs) go alone.
      std::uint16_t members[kRays];
      p.count = 0;
      for (std::size_t r = 0; r < count; ++r) {
        const Ray& ray = rays[group[r]];
        typename Batch::RaySetup s;
        if (!Batch::setup(ray, s)) {
          single(group[r]);
          continue;
        }
        members[p.count] = group[r];
        Packet::add(p, ray, s, ray.tmax);
      }
      if (p.count < Plan::kPacketMinRays) {
        for (std::size_t r = 0; r < p.count; ++r)
          single(members[r]);
        continue;
      }
      Packet::pad(p);
      const typename Packet::Interval iv = Line::interval(l, members, p, frame);
      run(p, iv, frame);
      for (std::size_t r = 0; r < p.count; ++r)
        store(r, members[r]);
    }
  }

  static unsigned octant(const Ray& ray) {
    return (__builtin_signbit(ray.dir.x) ? 1u : 0u) | (__builtin_signbit(ray.dir.y) ? 2u : 0u) |
           (__builtin_signbit(ray.dir.z) ? 4u : 0u);
  }

  // Whether rays[0, n) (n <= kRays) go as a packet, and if so gathers into p those that may
  // join it, their positions in index. single(i) answers each of the others: rays the
  // contract says miss, rays not ahead, rays of another octant than the first, or all of them
  // if the plan finds the group incoherent or too few remain.
  template <class Single>
  static bool gather(const Ray* rays, std::size_t n, float extent, typename Packet::Rays& p,
                     std::uint16_t* index, Single&& single) {
    p.count = 0;
    if (!Plan::coherent(rays, n, extent)) {
      for (std::size_t i = 0; i < n; ++i)
        single(i);
      return false;
    }
    unsigned first_octant = 8;
    for (std::size_t i = 0; i < n; ++i) {
      const Ray& ray = rays[i];
      typename Batch::RaySetup s;
      if (!Batch::setup(ray, s) || !Plan::ahead(ray)) {
        single(i);
        continue;
      }
      const unsigned o = octant(ray);
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

  // hits[i] = intersect(bvh, rays[i]), packets where the plan takes them.
  template <bool kBranchFree, bool kMasked>
  static void intersect(const BvhData& bvh, const Ray* rays, Hit* hits, std::size_t n) {
    const float extent = tree_extent(bvh);
    if (Plan::lines(rays, n, extent)) {
      const typename Packet::Rays* done = nullptr;
      lines(
          bvh, rays, n, extent,
          [&](typename Packet::Rays& q, const typename Packet::Interval& iv, const auto& frame) {
            Packet::template intersect<kBranchFree, kMasked>(bvh, q, iv, frame);
            done = &q;
          },
          [&](std::size_t i) {
            hits[i] = Tree::template intersect<kBranchFree, kMasked>(bvh, rays[i]);
          },
          [&](std::size_t r, std::size_t i) {
            hits[i] = {done->best[r], done->best_id[r]};
          });
      return;
    }
    typename Packet::Rays p;
    std::uint16_t index[kRays];
    for (std::size_t begin = 0; begin < n; begin += kRays) {
      const std::size_t count = n - begin > kRays ? kRays : n - begin;
      const auto single = [&](std::size_t i) {
        hits[begin + i] = Tree::template intersect<kBranchFree, kMasked>(bvh, rays[begin + i]);
      };
      if (!gather(rays + begin, count, extent, p, index, single)) continue;
      Packet::template intersect<kBranchFree, kMasked>(bvh, p);
      for (std::size_t r = 0; r < p.count; ++r)
        hits[begin + index[r]] = {p.best[r], p.best_id[r]};
    }
  }

  // blocked[i] = occluded(bvh, rays[i]), packets where the plan takes them.
  template <bool kMasked>
  static void occluded(const BvhData& bvh, const Ray* rays, bool* blocked, std::size_t n) {
    const float extent = tree_extent(bvh);
    if (Plan::lines(rays, n, extent)) {
      const typename Packet::Rays* done = nullptr;
      lines(
          bvh, rays, n, extent,
          [&](typename Packet::Rays& q, const typename Packet::Interval& iv, const auto& frame) {
            Packet::template occluded<kMasked>(bvh, q, iv, frame);
            done = &q;
          },
          [&](std::size_t i) { blocked[i] = Tree::template occluded<kMasked>(bvh, rays[i]); },
          [&](std::size_t r, std::size_t i) { blocked[i] = done->best[r] == -__builtin_inff(); });
      return;
    }
    typename Packet::Rays p;
    std::uint16_t index[kRays];
    for (std::size_t begin = 0; begin < n; begin += kRays) {
      const std::size_t count = n - begin > kRays ? kRays : n - begin;
      const auto single = [&](std::size_t i) {
        blocked[begin + i] = Tree::template occluded<kMasked>(bvh, rays[begin + i]);
      };
      if (!gather(rays + begin, count, extent, p, index, single)) continue;
      Packet::template occluded<kMasked>(bvh, p);
      for (std::size_t r = 0; r < p.count; ++r)
        blocked[begin + index[r]] = p.best[r] == -__builtin_inff();
    }
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
