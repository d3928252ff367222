// The wide BVH builder: binned SAH (Wald, "On fast Construction of SAH-based Bounding Volume
// Hierarchies", IEEE RT 2007) that prices a leaf by its batches, not its spheres, and grows each
// wide node by splitting its largest child until it has W (Wald, Benthin, Boulos, "Getting
// Rid of Packets", IEEE RT 2008). Deterministic: every step is a function of its input range
// only, the parallel reductions combine counts and min/max, which are exact in any order, and
// the parallel partition is stable over fixed blocks.
#include "bvh/build.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include <xsimd/xsimd.hpp>

#include "bvh/parallel.hpp"
#include "brute/validity.hpp"

#if SPHRAY_HAS_TBB
#include <tbb/info.h>
#include <tbb/task_arena.h>
#endif

namespace sphray::detail {
namespace {

constexpr float kInf = INFINITY;
// Bins per axis: 32 on large ranges, 16 below kFewBinsBelow spheres, where the bins' setup and
// sweep would cost more than the binning pass itself.
constexpr std::size_t kBins = 32;
constexpr std::size_t kFewBins = 16;
constexpr std::size_t kFewBinsBelow = 64;
// Past this depth every split is a median split, which at least halves a range: with ids
// below 2^32 the tree then stays within kBvhMaxDepth levels.
constexpr std::size_t kSahDepth = kBvhMaxDepth / 2;
// Spheres per block of the parallel partition, at most. Fixed for given options, so that the
// blocks, and with them the order the partition leaves, do not depend on the thread count.
constexpr std::size_t kBlock = 4096;

// Four floats, x, y, z and a spare lane, in one SIMD register: xsimd's baseline architecture
// (SSE2 on x86-64, NEON on AArch64) is 4 wide. The builder needs nothing wider: it is bound by
// memory, not arithmetic.
using Lanes = xsimd::batch<float, xsimd::default_arch>;
using LaneInts = xsimd::batch<std::int32_t, xsimd::default_arch>;
static_assert(Lanes::size == 4, "the builder's boxes are four lanes");

// A box with a spare lane per corner, so that growing it is one min and one max.
struct alignas(16) Box {
  float lo[4] = {kInf, kInf, kInf, kInf};
  float hi[4] = {-kInf, -kInf, -kInf, -kInf};

  void grow(const Lanes& l, const Lanes& h) {
    xsimd::min(Lanes::load_aligned(lo), l).store_aligned(lo);
    xsimd::max(Lanes::load_aligned(hi), h).store_aligned(hi);
  }
  void grow(const Box& b) { grow(Lanes::load_aligned(b.lo), Lanes::load_aligned(b.hi)); }
  void grow(const Lanes& point) { grow(point, point); }
  bool empty() const { return !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]); }
  // Half the surface area; the SAH only compares ratios. Infinite for unbounded boxes.
  float half_area() const {
    if (empty()) return 0.0f;
    const float x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
    const float a = x * y + y * z + z * x;
    return std::isnan(a) ? kInf : a;
  }
  // In double, so that boxes up to 10^100 wide keep a finite volume. Infinite for unbounded
  // boxes.
  double volume() const {
    if (empty()) return 0.0;
    const double v = (double{hi[0]} - lo[0]) * (double{hi[1]} - lo[1]) * (double{hi[2]} - lo[2]);
    return std::isnan(v) ? HUGE_VAL : v;
  }
};

// Half the side of a sphere's box on one axis: the radius, widened by 2^-20 of the
// coordinate's magnitude. That is more than the rounding of c -+ e, and enough to hold a grazing
// hit that the kernel's own rounding puts just outside the exact sphere.
float half_extent(float c, float r) {
  return r + (std::fabs(c) + r) * 0x1p-20f;
}

// One sphere as the builder sees it, 32 bytes: the centre and radius, the box's half extents
// and the id. The build partitions an array of these, so every pass over a range reads memory
// in order, and the leaves' spheres are copied out of it in order at the end. An invalid
// sphere (never hit) has centre 0, radius 0 and half extents -inf: its box c -+ e is empty, so
// it never widens a parent, and its centre still compares with the others.
struct alignas(16) Prim {
  float sphere[4];  // centre x, y, z; radius
  float extent[4];  // half extents x, y, z; the id's bits

  static Prim make(float x, float y, float z, float r, std::uint32_t id) {
    Prim p{{0.0f, 0.0f, 0.0f, 0.0f}, {-kInf, -kInf, -kInf, 0.0f}};
    if (valid_sphere({x, y, z}, r))
      p = {{x, y, z, r}, {half_extent(x, r), half_extent(y, r), half_extent(z, r), 0.0f}};
    p.extent[3] = std::bit_cast<float>(id);
    return p;
  }
  std::uint32_t id() const { return std::bit_cast<std::uint32_t>(extent[3]); }
  // The centre in lanes 0-2 (lane 3: the radius, which binning multiplies by 0).
  Lanes centre() const { return Lanes::load_aligned(sphere); }
  // Grows box by the sphere's box. The id's lane is zeroed first: as a float it is mostly
  // subnormal, which some processors handle in slow microcode.
  void grow(Box& box) const {
    const xsimd::batch_bool<float, xsimd::default_arch> xyz{true, true, true, false};
    const Lanes c = centre();
    const Lanes e = xsimd::select(xyz, Lanes::load_aligned(extent), Lanes(0.0f));
    box.grow(c - e, c + e);
  }
};
static_assert(std::is_trivially_default_constructible_v<Prim> && sizeof(Prim) == 32);

// A default-initialised array of prims: the builder writes every element before reading it.
struct Prims {
  explicit Prims(std::size_t n) : data(new Prim[n]), size(n) {}
  Prim& operator[](std::size_t i) { return data[i]; }
  const Prim& operator[](std::size_t i) const { return data[i]; }
  std::unique_ptr<Prim[]> data;
  std::size_t size;
};

// The box refit gives a sphere: the same arithmetic as the build's.
Box sphere_box(float x, float y, float z, float r) {
  Box b;
  Prim::make(x, y, z, r, 0).grow(b);
  return b;
}

// How a range's centres map to bins: (centre - origin) * scale, per axis, clamped to
// [0, last]. An axis with scale 0 is not binned (all its centres are equal).
struct Binning {
  Lanes origin, scale, last;

  // The bin of centre c on every axis; NaN (0 * inf) goes to bin 0. The builder computes every
  // bin index here, so binning and partition agree bit for bit.
  LaneInts bins(const Lanes& c) const {
    const Lanes zero(0.0f);
    const Lanes b = (c - origin) * scale;
    return xsimd::to_int(xsimd::min(xsimd::select(b > zero, b, zero), last));
  }
};

// A range of the prims that will become one child of a node.
struct Cluster {
  std::size_t begin, end;
  Box box;       // of the spheres
  Box centroid;  // of their centres

  std::size_t size() const { return end - begin; }
};

struct Bin {
  Box box;
  std::size_t count = 0;

  void grow(const Bin& b) {
    box.grow(b.box);
    count += b.count;
  }
};

struct Split {
  int axis = -1;
  std::int32_t bin = 0;  // spheres in bins <= bin go left
  Binning binning;
  Bin left, right;  // what each side will hold
};

class Builder {
 public:
  Builder(Prims& prims, std::size_t width, std::size_t parallel_min)
      : p_(prims),
        scratch_(prims.size),
        width_(width),
        parallel_min_(std::max<std::size_t>(parallel_min, 1024)),
        block_(std::clamp<std::size_t>(parallel_min_ / 4, 256, kBlock)) {
    // Parallel partitions note each prim's side here.
    if (p_.size >= parallel_min_) left_side_.resize(p_.size);
  }

  struct Node {
    struct Child {
      Cluster cluster;
      std::unique_ptr<Node> node;  // null for a leaf
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
    auto node = std::make_unique<Node>();
    std::vector<Cluster> parts{c};
    while (parts.size() < width_) {
      const int pick = largest_splittable(parts);
      if (pick < 0) break;
      const auto [left, right] = split(parts[pick], depth);
      parts[pick] = left;
      parts.insert(parts.begin() + pick + 1, right);
    }
    node->children.resize(parts.size());
    for (std::size_t k = 0; k < parts.size(); ++k)
      node->children[k].cluster = parts[k];
    build_children(*node, depth + 1);
    for (const auto& child : node->children)
      if (child.node) node->subtree_nodes += child.node->subtree_nodes;
    return node;
  }

 private:
  void build_children(Node& node, std::size_t depth) {
    TaskGroup group;
    for (auto& child : node.children) {
      if (child.cluster.size() <= width_) continue;
      if (child.cluster.size() >= parallel_min_)
        group.run([this, &child, depth] { child.node = build(child.cluster, depth); });
      else
        child.node = build(child.cluster, depth);
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
      scratch_[left ? l : r - 1] = p_[i];
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
    std::copy(&scratch_[c.begin], &scratch_[c.end], &p_[c.begin]);
    return l;
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
        scratch_[left_side_[i] ? l++ : r++] = p_[i];
    });
    parallel_for(blocks, 1, [&](std::size_t b) {
      std::copy(&scratch_[block_begin(b)], &scratch_[block_end(b)], &p_[block_begin(b)]);
    });
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
          for (int k = 0; k < 3; ++k) {
            if (scale[k] == 0.0f) continue;
            Bin& bin = b[k][static_cast<std::size_t>(index[k])];
            p.grow(bin.box);
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
  // the left; ties on the centre go by id, so the order is a function of the set alone.
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
    Prim* first = &p_[c.begin];
    std::nth_element(first, first + left, first + n, [axis](const Prim& a, const Prim& b) {
      const float ca = a.centre().get(axis), cb = b.centre().get(axis);
      return ca < cb || (ca == cb && a.id() < b.id());
    });
    return c.begin + left;
  }

  Prims& p_;
  Prims scratch_;
  std::vector<std::uint8_t> left_side_;  // per prim, in the parallel partition
  std::size_t width_;
  std::size_t parallel_min_;
  std::size_t block_;
};

// Where a leaf's spheres go: prims [begin, begin + count) to the slots from slot on.
struct LeafPlace {
  std::size_t begin, count, slot;
};

// Writes the built tree's nodes in depth-first pre-order (a parent before its children, which
// refit relies on), and gives every leaf its own batch of width sphere slots: its reference is
// its first slot, a multiple of the width, plus its count - 1. An aligned leaf is read as one
// batch without a cache-line split, and the lanes past its count hold never-hit padding, not
// the next leaf's spheres (whose extra hits only made the closest-hit fold longer).
class Flattener {
 public:
  explicit Flattener(BvhArrays& out) : out_(out), w_(out.width) {}

  std::vector<LeafPlace> leaves;
  std::size_t slots_used = 0;  // a multiple of the width

  void write(const Builder::Node& node, std::size_t index) {
    float* slots = out_.nodes.get() + index * kBvhNodeRows * w_;
    std::size_t next = index + 1;
    for (std::size_t k = 0; k < w_; ++k) {
      const Builder::Node::Child* child = k < node.children.size() ? &node.children[k] : nullptr;
      std::uint32_t ref = kBvhEmptySlot;
      if (child && child->node) {
        ref = static_cast<std::uint32_t>(next);
        write(*child->node, next);
        next += child->node->subtree_nodes;
      } else if (child) {
        const std::size_t count = child->cluster.size();
        ref = kBvhLeafBit | static_cast<std::uint32_t>(slots_used + count - 1);
        leaves.push_back({child->cluster.begin, count, slots_used});
        slots_used += w_;
      }
      write_box(slots, k, child ? child->cluster.box : Box{});
      slots[6 * w_ + k] = std::bit_cast<float>(ref);
    }
  }

 private:
  void write_box(float* slots, std::size_t k, const Box& b) {
    for (int axis = 0; axis < 3; ++axis) {
      slots[(2 * axis) * w_ + k] = b.lo[axis];
      slots[(2 * axis + 1) * w_ + k] = b.hi[axis];
    }
  }

  BvhArrays& out_;
  std::size_t w_;
};

Prims make_prims(SphereView v) {
  Prims p(v.count);
  parallel_for(v.count, kBlock, [&](std::size_t i) {
    p[i] = Prim::make(v.cx[i], v.cy[i], v.cz[i], v.radius[i], static_cast<std::uint32_t>(i));
  });
  return p;
}

template <class T>
BvhArrays::AlignedArray<T> allocate(std::size_t n) {
  return BvhArrays::AlignedArray<T>(
      static_cast<T*>(::operator new[](n * sizeof(T), std::align_val_t{64})));
}

// The zeroed nodes of a tree of nodes nodes.
void allocate_nodes(BvhArrays& out, std::size_t nodes) {
  if (nodes >= kBvhEmptySlot) throw std::length_error("sphray::SphereBVH: too many spheres");
  out.nodes = allocate<float>(nodes * kBvhNodeRows * out.width);
  std::fill_n(out.nodes.get(), nodes * kBvhNodeRows * out.width, 0.0f);
  out.node_count = nodes;
}

// The sphere slots, rounded to 16 floats so that each of the four arrays starts on a cache
// line, all never hit (radius 0, id kNoHit) until the leaves' spheres are written.
void allocate_slots(BvhArrays& out, std::size_t slots) {
  out.slots = (slots + 15) / 16 * 16;
  if (out.slots >= kBvhLeafBit) throw std::length_error("sphray::SphereBVH: too many spheres");
  out.spheres = allocate<float>(4 * out.slots);
  out.ids = allocate<std::uint32_t>(out.slots);
  std::fill_n(out.spheres.get(), 4 * out.slots, 0.0f);
  std::fill_n(out.ids.get(), out.slots, kNoHit);
}

// The spheres and ids of the built tree: each leaf's prims to its slots.
void write_spheres(BvhArrays& out, const Prims& prims, const std::vector<LeafPlace>& leaves) {
  float* x = out.spheres.get();
  float *y = x + out.slots, *z = y + out.slots, *r = z + out.slots;
  parallel_for(leaves.size(), kBlock / 16, [&](std::size_t k) {
    const LeafPlace& leaf = leaves[k];
    for (std::size_t j = 0; j < leaf.count; ++j) {
      const Prim& p = prims[leaf.begin + j];
      const std::size_t i = leaf.slot + j;
      x[i] = p.sphere[0];
      y[i] = p.sphere[1];
      z[i] = p.sphere[2];
      r[i] = p.sphere[3];
      out.ids[i] = p.id();
    }
  });
}

// Copies sphere ids[slot] of v into every slot that holds one, for refit.
void copy_spheres(BvhArrays& out, SphereView v) {
  float* x = out.spheres.get();
  float *y = x + out.slots, *z = y + out.slots, *r = z + out.slots;
  parallel_for(out.slots, kBlock, [&](std::size_t slot) {
    const std::uint32_t id = out.ids[slot];
    if (id == kNoHit) return;
    x[slot] = v.cx[id];
    y[slot] = v.cy[id];
    z[slot] = v.cz[id];
    r[slot] = v.radius[id];
  });
}

// The leaf boxes' summed volume over the root box's (BvhArrays::leaf_overlap), from the
// written nodes: one pass over them, after a build or a refit. Every leaf box lies in the root
// box, so the ratio is at most the leaf count; the clamp only keeps the cast to float defined
// whatever the input.
float measure_leaf_overlap(const BvhArrays& tree) {
  const std::size_t w = tree.width;
  double leaf_volume = 0.0;
  Box root;
  for (std::size_t n = 0; n < tree.node_count; ++n) {
    const float* slots = tree.nodes.get() + n * kBvhNodeRows * w;
    for (std::size_t k = 0; k < w; ++k) {
      const std::uint32_t ref = std::bit_cast<std::uint32_t>(slots[6 * w + k]);
      if (ref == kBvhEmptySlot || (n != 0 && (ref & kBvhLeafBit) == 0)) continue;
      Box box;
      for (int axis = 0; axis < 3; ++axis) {
        box.lo[axis] = slots[(2 * axis) * w + k];
        box.hi[axis] = slots[(2 * axis + 1) * w + k];
      }
      if (n == 0) root.grow(box);
      if (ref & kBvhLeafBit) leaf_volume += box.volume();
    }
  }
  const double overlap = leaf_volume / root.volume();
  return std::isfinite(overlap) ? static_cast<float>(std::min(overlap, 1e30)) : 0.0f;
}

BvhArrays build_here(SphereView v, std::size_t width, std::size_t parallel_min) {
  BvhArrays out;
  out.width = width;
  out.source_count = v.count;
  if (v.count == 0) return out;
  Prims prims = make_prims(v);
  Builder builder(prims, width, parallel_min);
  // The root is always a node, even over a single leaf, so traversal starts the same way.
  Builder::Node root;
  const Cluster all = builder.cluster(0, v.count);
  if (v.count <= width) {
    root.children.resize(1);
    root.children[0].cluster = all;
  } else {
    root = std::move(*builder.build(all, 0));
  }
  allocate_nodes(out, root.subtree_nodes);
  Flattener flat(out);
  flat.write(root, 0);
  allocate_slots(out, flat.slots_used);
  write_spheres(out, prims, flat.leaves);
  out.leaf_overlap = measure_leaf_overlap(out);
  return out;
}

}  // namespace

BvhData BvhArrays::data() const {
  BvhData d;
  d.width = width;
  d.nodes = nodes.get();
  d.node_count = node_count;
  if (slots != 0) {
    const float* x = spheres.get();
    d.spheres = {x, x + slots, x + 2 * slots, x + 3 * slots, slots, slots};
  }
  d.ids = ids.get();
  d.count = source_count;
  d.memory_bytes = memory_bytes();
  d.leaf_overlap = leaf_overlap;
  return d;
}

std::size_t BvhArrays::memory_bytes() const {
  return node_count * kBvhNodeRows * width * sizeof(float) +
         slots * (4 * sizeof(float) + sizeof(std::uint32_t));
}

BvhArrays build_bvh(SphereView spheres, std::size_t width, const BvhBuildOptions& options) {
  if (spheres.count > (std::size_t{1} << 31))
    throw std::length_error("sphray::SphereBVH: more than 2^31 spheres");
#if SPHRAY_HAS_TBB
  // More threads than the machine runs would only make oneTBB warn: the tree is the same.
  const int cores = tbb::info::default_concurrency();
  const int use = options.threads == 0 ? cores : std::min(cores, static_cast<int>(options.threads));
  tbb::task_arena arena(use);
  return arena.execute([&] { return build_here(spheres, width, options.parallel_min); });
#else
  return build_here(spheres, width, options.parallel_min);
#endif
}

void refit_bvh(BvhArrays& tree, SphereView v) {
  if (v.count != tree.source_count)
    throw std::invalid_argument("sphray::SphereBVH::refit: the sphere count changed");
  if (tree.node_count == 0) return;
  copy_spheres(tree, v);
  const BvhData d = tree.data();
  const std::size_t w = tree.width;
  // Children come after their parent, so a reverse sweep sees every child's boxes first.
  for (std::size_t n = tree.node_count; n-- > 0;) {
    float* slots_of = tree.nodes.get() + n * kBvhNodeRows * w;
    for (std::size_t k = 0; k < w; ++k) {
      const std::uint32_t ref = std::bit_cast<std::uint32_t>(slots_of[6 * w + k]);
      if (ref == kBvhEmptySlot) continue;
      Box box;
      if (ref & kBvhLeafBit) {
        const std::size_t first = ref & kBvhLeafFirstMask & ~(w - 1);
        const std::size_t count = (ref & (w - 1)) + 1;
        for (std::size_t i = first; i < first + count; ++i)
          box.grow(
              sphere_box(d.spheres.cx[i], d.spheres.cy[i], d.spheres.cz[i], d.spheres.radius[i]));
      } else {
        const float* child = tree.nodes.get() + std::size_t{ref} * kBvhNodeRows * w;
        for (std::size_t j = 0; j < w; ++j)
          for (int axis = 0; axis < 3; ++axis) {
            box.lo[axis] = std::min(box.lo[axis], child[(2 * axis) * w + j]);
            box.hi[axis] = std::max(box.hi[axis], child[(2 * axis + 1) * w + j]);
          }
      }
      for (int axis = 0; axis < 3; ++axis) {
        slots_of[(2 * axis) * w + k] = box.lo[axis];
        slots_of[(2 * axis + 1) * w + k] = box.hi[axis];
      }
    }
  }
  tree.leaf_overlap = measure_leaf_overlap(tree);
}

}  // namespace sphray::detail
