// The wide BVH builder: binned SAH (Wald, "On fast Construction of SAH-based Bounding Volume
// Hierarchies", IEEE RT 2007) that prices a leaf by its batches, not its spheres, and grows each
// wide node by splitting its largest child until it has W (Wald, Benthin, Boulos, "Getting
// Rid of Packets", IEEE RT 2008). Deterministic: every step is a function of its input range
// only, the parallel reductions combine counts and min/max, which are exact in any order, and
// the parallel partition is stable over fixed blocks. Its tree of nodes is flattened into the
// traversal's layout by build.cpp.
#pragma once

#include <algorithm>
#include <array>
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
// Past this depth every split is a median split, which at least halves a range: with ids
// below 2^32 the tree then stays within kBvhMaxDepth levels.
constexpr std::size_t kSahDepth = kBvhMaxDepth / 2;

class Builder {
 public:
  Builder(Prims& prims, std::size_t width, std::size_t parallel_min, ProgressCount& progress)
      : p_(prims),
        progress_(progress),
        scratch_(prims.size),
        width_(width),
        parallel_min_(std::max<std::size_t>(parallel_min, 1024)),
        block_(std::clamp<std::size_t>(parallel_min_ / 4, 256, kBlock)) {
    // Parallel partitions note each prim's side here.
    if (p_.size >= parallel_min_) left_side_.resize(p_.size);
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
        const auto goes_left = [&s](const Lanes& centre) {
          alignas(16) std::int32_t bins[4];
          s.binning.bins(centre).store_aligned(bins);
          return bins[s.axis] <= s.bin;
        };
        Box left_centroids, right_centroids;
        const std::size_t mid =
            c.size() >= parallel_min_
                ? partition_parallel(c, goes_left, left_centroids, right_centroids)
                : partition_serial(c, goes_left, left_centroids, right_centroids);
        // The bins already hold both sides' boxes: no pass over the spheres to find them.
        if (mid == c.begin + s.left.count)
          return {{c.begin, mid, s.left.box, left_centroids},
                  {mid, c.end, s.right.box, right_centroids}};
      }
    }
    const std::size_t mid = median_split(c);
    return {cluster(c.begin, mid), cluster(mid, c.end)};
  }

  // One pass that copies each prim to the scratch array, lefts from the front and rights from
  // the back, growing each side's centre bounds, then a copy back. Branch-free: which side a
  // sphere goes is a coin toss, and a branch on it would mispredict half the time.
  template <class Left>
  std::size_t partition_serial(const Cluster& c, const Left& goes_left, Box& left_centroids,
                               Box& right_centroids) {
    Lanes left_lo(kInf), left_hi(-kInf), right_lo(kInf), right_hi(-kInf);
    std::size_t l = c.begin, r = c.end;
    for (std::size_t i = c.begin; i < c.end; ++i) {
      const Lanes centre = p_[i].centre();
      const bool left = goes_left(centre);
      p_.copy(i, scratch_, left ? l : r - 1);
      l += left;
      r -= !left;
      const xsimd::batch_bool<float, xsimd::default_arch> to_left(left);
      left_lo = xsimd::select(to_left, xsimd::min(left_lo, centre), left_lo);
      left_hi = xsimd::select(to_left, xsimd::max(left_hi, centre), left_hi);
      right_lo = xsimd::select(to_left, right_lo, xsimd::min(right_lo, centre));
      right_hi = xsimd::select(to_left, right_hi, xsimd::max(right_hi, centre));
    }
    left_centroids.grow(left_lo, left_hi);
    right_centroids.grow(right_lo, right_hi);
    copy_back(c.begin, c.end);
    return l;
  }

  // The scratch array's [begin, end) back to the prims.
  void copy_back(std::size_t begin, std::size_t end) {
    std::copy(&scratch_[begin], &scratch_[end], &p_[begin]);
    std::copy(&scratch_.ids[begin], &scratch_.ids[end], &p_.ids[begin]);
  }

  // A stable partition over fixed blocks: note each prim's side and count each block's, then
  // copy every prim to its place in the scratch array, and back. The same order whatever the
  // thread count.
  template <class Left>
  std::size_t partition_parallel(const Cluster& c, const Left& goes_left, Box& left_centroids,
                                 Box& right_centroids) {
    struct Block {
      std::size_t left = 0;
      Box left_centroids, right_centroids;
    };
    const std::size_t blocks = (c.size() + block_ - 1) / block_;
    const auto block_begin = [&](std::size_t b) { return c.begin + b * block_; };
    const auto block_end = [&](std::size_t b) {
      return std::min(c.begin + (b + 1) * block_, c.end);
    };
    std::vector<Block> info(blocks);
    parallel_for(blocks, 1, [&](std::size_t b) {
      Block& k = info[b];
      for (std::size_t i = block_begin(b); i < block_end(b); ++i) {
        const Lanes centre = p_[i].centre();
        const bool left = goes_left(centre);
        left_side_[i] = left;
        k.left += left;
        (left ? k.left_centroids : k.right_centroids).grow(centre);
      }
    });
    std::vector<std::size_t> left_at(blocks), right_at(blocks);
    std::size_t lefts = 0;
    for (std::size_t b = 0; b < blocks; ++b) {
      left_at[b] = lefts;
      lefts += info[b].left;
      left_centroids.grow(info[b].left_centroids);
      right_centroids.grow(info[b].right_centroids);
    }
    for (std::size_t b = 0, rights = 0; b < blocks; ++b) {
      right_at[b] = lefts + rights;
      rights += (block_end(b) - block_begin(b)) - info[b].left;
    }
    parallel_for(blocks, 1, [&](std::size_t b) {
      std::size_t l = c.begin + left_at[b], r = c.begin + right_at[b];
      for (std::size_t i = block_begin(b); i < block_end(b); ++i)
        p_.copy(i, scratch_, left_side_[i] ? l++ : r++);
    });
    parallel_for(blocks, 1, [&](std::size_t b) { copy_back(block_begin(b), block_end(b)); });
    return c.begin + lefts;
  }

  // Cost of a side: its area times its leaf batches. A leaf of W spheres costs what a leaf of
  // one does, so the SAH prefers splits that fill batches.
  float side_cost(const Box& box, std::size_t count) const {
    return box.half_area() * static_cast<float>((count + width_ - 1) / width_);
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
    const Bins bins = reduce_range(
        c.begin, c.end, parallel_min_, block_, Bins{},
        [&](Bins& b, std::size_t i) {
          const Prim& p = p_[i];
          alignas(16) std::int32_t index[4];
          binning.bins(p.centre()).store_aligned(index);
          const auto [lo, hi] = p.bounds();
          for (int k = 0; k < 3; ++k) {
            if (scale[k] == 0.0f) continue;
            Bin& bin = b[k][static_cast<std::size_t>(index[k])];
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
          best = {k, static_cast<std::int32_t>(i), binning, left, right[i]};
        }
      }
    }
    return best;
  }

  // Splits at the median centre along the widest centroid axis, rounded to whole batches on
  // the left; ties on the centre go by id, so the order is a function of the set alone. What
  // nth_element orders is the range's positions (in the scratch ids), not the prims and their
  // ids, two arrays; both are then gathered in that order, which is the order nth_element
  // would have left the prims in.
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
    std::uint32_t* order = &scratch_.ids[c.begin];
    std::iota(order, order + n, 0u);
    std::nth_element(order, order + left, order + n, [&](std::uint32_t a, std::uint32_t b) {
      const float ca = prims[a].sphere[axis], cb = prims[b].sphere[axis];
      return ca < cb || (ca == cb && ids[a] < ids[b]);
    });
    // Element j's position is read before its id overwrites it.
    for (std::size_t j = 0; j < n; ++j)
      p_.copy(c.begin + order[j], scratch_, c.begin + j);
    copy_back(c.begin, c.end);
    return c.begin + left;
  }

  Prims& p_;
  ProgressCount& progress_;
  Prims scratch_;
  std::vector<std::uint8_t> left_side_;  // per prim, in the parallel partition
  std::size_t width_;
  std::size_t parallel_min_;
  std::size_t block_;
};

}  // namespace sphray::detail
