// The wide BVH builder: binned SAH (Wald, "On fast Construction of SAH-based Bounding Volume
// Hierarchies", IEEE RT 2007) that prices a leaf by its batches, not its spheres, and grows each
// wide node by splitting its largest child until it has W (Wald, Benthin, Boulos, "Getting
// Rid of Packets", IEEE RT 2008). Deterministic: every step is a function of its input range
// only, the parallel reductions combine counts and min/max, which are exact in any order, and
// the parallel partition works over fixed blocks. Its tree of nodes is flattened into the
// traversal's layout by build.cpp.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <numeric>
#include <utility>
#include <vector>

#include "bvh/binning.hpp"
#include "bvh/build_progress.hpp"
#include "bvh/bvh_data.hpp"
#include "bvh/parallel.hpp"
#include "bvh/prim.hpp"

namespace sphray::detail {

// Bins per axis: 32 on large ranges, 16 below kFewBinsBelow spheres, where the bins' setup and
// sweep would cost more than the binning pass itself.
constexpr std::size_t kBins = 32;
constexpr std::size_t kFewBins = 16;
constexpr std::size_t kFewBinsBelow = 64;
// A range of more spheres than twice this chooses its split from kBinSamples to twice as many of
// them, evenly spaced, and the partition, which reads every sphere anyway, grows its sides'
// boxes: the top levels of a large tree then read their spheres once a split rather than twice,
// with splits whose cost differs from the full binning's by a fraction of a percent
// (docs/bvh.md).
constexpr std::size_t kBinSamples = std::size_t{1} << 14;
// Past this depth every split is a median split, which at least halves a range: with ids
// below 2^32 the tree then stays within kBvhMaxDepth levels.
constexpr std::size_t kSahDepth = kBvhMaxDepth / 2;

// Ranges of positions, in order, and the k-th position over all of them.
class Runs {
  struct Run {
    std::size_t begin, end, before;  // before: positions in the runs ahead of it
  };

 public:
  void add(std::size_t begin, std::size_t end) {
    if (begin < end) runs_.push_back({begin, end, total_});
    total_ += end > begin ? end - begin : 0;
  }
  std::size_t total() const { return total_; }

  class Cursor {
   public:
    Cursor(const Runs& runs, std::size_t run, std::size_t at)
        : runs_(runs.runs_), run_(run), at_(at) {}
    std::size_t next() {
      if (at_ == runs_[run_].end) at_ = runs_[++run_].begin;
      return at_++;
    }

   private:
    const std::vector<Run>& runs_;
    std::size_t run_, at_;
  };
  // A cursor whose next() is the k-th position (k < total()).
  Cursor at(std::size_t k) const {
    const auto run = std::upper_bound(runs_.begin(), runs_.end(), k,
                                      [](std::size_t v, const Run& r) { return v < r.before; });
    const std::size_t index = static_cast<std::size_t>(run - runs_.begin()) - 1;
    return Cursor(*this, index, runs_[index].begin + (k - runs_[index].before));
  }

 private:
  std::vector<Run> runs_;
  std::size_t total_ = 0;
};

class Builder {
 public:
  Builder(Prims& prims, std::size_t width, std::size_t parallel_min, ProgressCount& progress)
      : p_(prims),
        progress_(progress),
        width_(width),
        parallel_min_(std::max<std::size_t>(parallel_min, 1024)),
        block_(std::clamp<std::size_t>(parallel_min_ / 4, 256, kBlock)),
        width_shift_(static_cast<unsigned>(std::countr_zero(width))) {
    assert(std::has_single_bit(width));
  }

  struct Node {
    // A child keeps its range and box, not its centre bounds, which only its own build reads:
    // the builder's nodes stay alive until the tree is written out (build.cpp).
    struct Child {
      std::size_t begin = 0, end = 0;
      Box box;
      std::unique_ptr<Node> node;  // null for a leaf

      Child() = default;
      explicit Child(const Cluster& c) : begin(c.begin), end(c.end), box(c.box) {}
      std::size_t size() const { return end - begin; }
    };
    std::vector<Child> children;
    std::size_t subtree_nodes = 1;  // this node and every node below it
  };

  Cluster cluster(std::size_t begin, std::size_t end) const {
    struct Acc {
      Box box, centroid;
    };
    const Acc acc = reduce_range(
        begin, end, parallel_min_, block_, Acc{},
        [&](Acc& a, std::size_t i) {
          p_[i].grow(a.box);
          a.centroid.grow(p_[i].centre());
        },
        [](Acc& a, const Acc& b) {
          a.box.grow(b.box);
          a.centroid.grow(b.centroid);
        });
    return {begin, end, acc.box, acc.centroid};
  }

  // The node over c, whose size exceeds the width.
  std::unique_ptr<Node> build(const Cluster& c, std::size_t depth) {
    std::vector<Cluster> parts{c};
    parts.reserve(width_);
    while (parts.size() < width_) {
      const int pick = largest_splittable(parts);
      if (pick < 0) break;
      // A split of millions of spheres takes a good part of a second: ask before each.
      if (parts[pick].size() >= ProgressCount::kAskFrom) progress_.ask();
      const auto [left, right] = split(parts[pick], depth);
      parts[pick] = left;
      parts.insert(parts.begin() + pick + 1, right);
    }
    auto node = std::make_unique<Node>();
    node->children.reserve(parts.size());
    for (const Cluster& part : parts)
      node->children.emplace_back(part);
    build_children(*node, parts, c.size() >= ProgressCount::kAskFrom, depth + 1);
    for (const auto& child : node->children)
      if (child.node) node->subtree_nodes += child.node->subtree_nodes;
    return node;
  }

 private:
  // counted: whether to count the small children's spheres as placed (the node itself is not
  // small: below it, each sphere is in exactly one small child of a large node).
  void build_children(Node& node, const std::vector<Cluster>& parts, bool counted,
                      std::size_t depth) {
    TaskGroup group;
    for (std::size_t k = 0; k < parts.size(); ++k) {
      Node::Child& child = node.children[k];
      const Cluster& part = parts[k];
      const std::size_t size = part.size();
      if (size > width_ && size >= parallel_min_)
        group.run([this, &child, &part, depth] { child.node = build(part, depth); });
      else if (size > width_)
        child.node = build(part, depth);
      if (counted && size < ProgressCount::kAskFrom) progress_.placed(size);
    }
    group.wait();
  }

  // The part to split next: the one with the largest area among those over the width.
  int largest_splittable(const std::vector<Cluster>& parts) const {
    int pick = -1;
    for (std::size_t k = 0; k < parts.size(); ++k) {
      if (parts[k].size() <= width_) continue;
      if (pick < 0 || parts[k].box.half_area() > parts[pick].box.half_area())
        pick = static_cast<int>(k);
    }
    return pick;
  }

  std::pair<Cluster, Cluster> split(const Cluster& c, std::size_t depth) {
    if (depth < kSahDepth) {
      const Split s =
          c.size() < kFewBinsBelow ? best_sah_split<kFewBins>(c) : best_sah_split<kBins>(c);
      if (s.axis >= 0) {
        // The bins already hold both sides' boxes, unless they saw only a sample: then the
        // partition finds them.
        Sides sides;
        const std::size_t mid =
            s.sampled ? partition<true>(c, s, sides) : partition<false>(c, s, sides);
        if (s.sampled && mid > c.begin && mid < c.end)
          return {{c.begin, mid, sides.left.box, sides.left.centroids},
                  {mid, c.end, sides.right.box, sides.right.centroids}};
        if (!s.sampled && mid == c.begin + s.left.count)
          return {{c.begin, mid, s.left.box, sides.left.centroids},
                  {mid, c.end, s.right.box, sides.right.centroids}};
      }
    }
    const std::size_t mid = median_split(c);
    return {cluster(c.begin, mid), cluster(mid, c.end)};
  }

  // What a partition learns of each side as it reads the prims: its centres' bounds and, when
  // asked (Boxed), its box.
  struct Side {
    Box box, centroids;
    void grow(const Side& s) {
      box.grow(s.box);
      centroids.grow(s.centroids);
    }
  };
  struct Sides {
    Side left, right;
    void grow(const Sides& s) {
      left.grow(s.left);
      right.grow(s.right);
    }
  };

  // Split s as a plane: a prim goes left if its bin on s's axis is at most s.bin, as
  // Binning::bins() would compute it (the same two operations on the same lane; the clamp to
  // the last bin cannot move a bin across s.bin, and a NaN goes to bin 0), without the other
  // axes. The axis's origin and scale are read out of their lanes once, not per prim.
  struct SplitPlane {
    std::size_t axis;
    float origin, scale, limit;

    explicit SplitPlane(const Split& s)
        : axis(static_cast<std::size_t>(s.axis)),
          origin(s.binning.origin.get(axis)),
          scale(s.binning.scale.get(axis)),
          limit(static_cast<float>(s.bin + 1)) {}
    bool goes_left(const Prim& p) const { return !((p.sphere[axis] - origin) * scale >= limit); }
  };

  template <bool Boxed>
  std::size_t partition(const Cluster& c, const Split& s, Sides& sides) {
    if (c.size() >= parallel_min_) return partition_parallel<Boxed>(c, s, sides);
    return partition_serial<Boxed>(c.begin, c.end, s, sides);
  }

  // Partitions [begin, end) in place, lefts first, in one branch-free pass (which side a
  // sphere goes is a coin toss: a branch on it would mispredict half the time): every prim
  // swaps with the first right so far, which moves on past it if it goes left. The lefts keep
  // their order; the order the rights end in is a function of the range alone. Returns where
  // the rights start.
  template <bool Boxed>
  std::size_t partition_serial(std::size_t begin, std::size_t end, const Split& s, Sides& sides) {
    BoxLanes left_centroids, right_centroids, left_box, right_box;
    const SplitPlane plane(s);
    std::size_t l = begin;
    for (std::size_t i = begin; i < end; ++i) {
      const Prim prim = p_[i];
      const bool to_left = plane.goes_left(prim);
      p_.swap(i, l);
      l += to_left;
      const LaneMask mask(to_left);
      const Lanes centre = prim.centre();
      left_centroids.grow_if(mask, centre, centre);
      right_centroids.grow_if(!mask, centre, centre);
      if constexpr (Boxed) {
        const auto [lo, hi] = prim.bounds();
        left_box.grow_if(mask, lo, hi);
        right_box.grow_if(!mask, lo, hi);
      }
    }
    left_centroids.grow(sides.left.centroids);
    right_centroids.grow(sides.right.centroids);
    if constexpr (Boxed) {
      left_box.grow(sides.left.box);
      right_box.grow(sides.right.box);
    }
    return l;
  }

  // The same in place in parallel, over fixed blocks so that the order is the same whatever
  // the thread count: each block partitions itself, then the rights left in front of the
  // split and the lefts behind it, as many of each, swap in pairs, the k-th with the k-th.
  // No scratch copy of the prims: it would have been the build's largest array after them
  // (issue 34).
  template <bool Boxed>
  std::size_t partition_parallel(const Cluster& c, const Split& s, Sides& sides) {
    struct Block {
      std::size_t begin, end, rights_begin;  // after its own partition
      Sides sides;
    };
    const std::size_t blocks = (c.size() + block_ - 1) / block_;
    std::vector<Block> info(blocks);
    parallel_for(blocks, 1, [&](std::size_t b) {
      Block& k = info[b];
      k.begin = c.begin + b * block_;
      k.end = std::min(k.begin + block_, c.end);
      k.rights_begin = partition_serial<Boxed>(k.begin, k.end, s, k.sides);
    });
    std::size_t mid = c.begin;
    for (const Block& k : info) {
      mid += k.rights_begin - k.begin;
      sides.grow(k.sides);
    }
    // Misplaced: each block's rights before mid, and its lefts from mid on.
    Runs rights_in_front, lefts_behind;
    for (const Block& k : info) {
      rights_in_front.add(k.rights_begin, std::min(k.end, mid));
      lefts_behind.add(std::max(k.begin, mid), k.rights_begin);
    }
    const std::size_t misplaced = rights_in_front.total();
    parallel_for((misplaced + block_ - 1) / block_, 1, [&](std::size_t b) {
      const std::size_t first = b * block_, last = std::min(first + block_, misplaced);
      Runs::Cursor front = rights_in_front.at(first), back = lefts_behind.at(first);
      for (std::size_t k = first; k < last; ++k)
        p_.swap(front.next(), back.next());
    });
    return mid;
  }

  // Cost of a side: its area times its leaf batches. A leaf of W spheres costs what a leaf of
  // one does, so the SAH prefers splits that fill batches. The width is a power of two: a
  // shift, not a division, which the sweep would otherwise do twice per candidate.
  float side_cost(const Box& box, std::size_t count) const {
    return box.half_area() * static_cast<float>((count + width_ - 1) >> width_shift_);
  }

  template <std::size_t Count>
  Split best_sah_split(const Cluster& c) const {
    using Bins = std::array<std::array<Bin, Count>, 3>;
    alignas(16) float scale[4] = {}, origin[4] = {};
    for (int k = 0; k < 3; ++k) {
      origin[k] = c.centroid.lo[k];
      const float extent = c.centroid.hi[k] - c.centroid.lo[k];
      // Slightly under Count / extent, so the largest centroid lands in the last bin.
      const float s = static_cast<float>(Count) * (1.0f - 0x1p-20f) / extent;
      scale[k] = extent > 0.0f && std::isfinite(s) ? s : 0.0f;
    }
    const Binning binning{Lanes::load_aligned(origin), Lanes::load_aligned(scale),
                          Lanes(static_cast<float>(Count - 1))};
    // A large range bins an evenly spaced sample of its spheres (kBinSamples).
    const std::size_t stride = std::max<std::size_t>(c.size() / kBinSamples, 1);
    const Bins bins = reduce_range(
        0, c.size() / stride, parallel_min_, block_, Bins{},
        [&](Bins& b, std::size_t j) {
          const Prim& p = p_[c.begin + j * stride];
          const LaneInts index = binning.bins(p.centre());
          const auto [lo, hi] = p.bounds();
          // An axis not binned (scale 0) has every sphere in bin 0, which is never read: no
          // branch in the loop.
          for (int k = 0; k < 3; ++k) {
            Bin& bin = b[k][static_cast<std::size_t>(index.get(static_cast<std::size_t>(k)))];
            bin.box.grow(lo, hi);
            ++bin.count;
          }
        },
        [](Bins& a, const Bins& b) {
          for (int k = 0; k < 3; ++k)
            for (std::size_t i = 0; i < Count; ++i)
              a[k][i].grow(b[k][i]);
        });
    Split best;
    float best_cost = kInf;
    for (int k = 0; k < 3; ++k) {
      if (scale[k] == 0.0f) continue;
      // right[i]: the bins above i, accumulated from the top.
      std::array<Bin, Count> right;
      Bin above;
      for (std::size_t i = Count - 1; i > 0; --i) {
        above.grow(bins[k][i]);
        right[i - 1] = above;
      }
      Bin left;
      for (std::size_t i = 0; i + 1 < Count; ++i) {
        left.grow(bins[k][i]);
        if (left.count == 0 || right[i].count == 0) continue;
        const float cost =
            side_cost(left.box, left.count) + side_cost(right[i].box, right[i].count);
        if (cost < best_cost) {
          best_cost = cost;
          best = {k, static_cast<std::int32_t>(i), binning, left, right[i], stride > 1};
        }
      }
    }
    return best;
  }

  // Splits at the median centre along the widest centroid axis, rounded to whole batches on
  // the left; ties on the centre go by id, so the order is a function of the set alone. What
  // nth_element orders is the range's positions, not the prims and their ids, two arrays;
  // both are then permuted in place into that order (following each cycle of the
  // permutation), which is the order nth_element would have left the prims in.
  std::size_t median_split(const Cluster& c) {
    int axis = 0;
    float widest = -1.0f;
    for (int k = 0; k < 3; ++k) {
      const float extent = c.centroid.hi[k] - c.centroid.lo[k];
      if (extent > widest) {
        widest = extent;
        axis = k;
      }
    }
    const std::size_t n = c.size();
    std::size_t left = (n / 2 + width_ - 1) / width_ * width_;
    if (left >= n) left = n / 2;
    const Prim* prims = &p_[c.begin];
    const std::uint32_t* ids = &p_.ids[c.begin];
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(left), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) {
                       const float ca = prims[a].sphere[axis], cb = prims[b].sphere[axis];
                       return ca < cb || (ca == cb && ids[a] < ids[b]);
                     });
    permute(c.begin, order);
    return c.begin + left;
  }

  // Moves the prim at begin + order[j] to begin + j for every j, in place; order ends as the
  // identity.
  void permute(std::size_t begin, std::vector<std::uint32_t>& order) {
    for (std::size_t start = 0; start < order.size(); ++start) {
      if (order[start] == start) continue;
      // The cycle through start: each place takes the prim of the next, the last start's.
      const Prim held = p_[begin + start];
      const std::uint32_t held_id = p_.ids[begin + start];
      std::size_t j = start;
      while (order[j] != start) {
        const std::size_t from = order[j];
        p_[begin + j] = p_[begin + from];
        p_.ids[begin + j] = p_.ids[begin + from];
        order[j] = static_cast<std::uint32_t>(j);
        j = from;
      }
      p_[begin + j] = held;
      p_.ids[begin + j] = held_id;
      order[j] = static_cast<std::uint32_t>(j);
    }
  }

  Prims& p_;
  ProgressCount& progress_;
  std::size_t width_;
  std::size_t parallel_min_;
  std::size_t block_;
  unsigned width_shift_;  // log2 of the width
};

}  // namespace sphray::detail
