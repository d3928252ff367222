// The wide BVH builder: binned SAH (Wald, "On fast Construction of SAH-based Bounding Volume
// Hierarchies", IEEE RT 2007) that prices a leaf by its batches, not its spheres, and grows each
// wide node by splitting its largest child until it has W (Wald, Benthin, Boulos, "Getting
// Rid of Packets", IEEE RT 2008). Deterministic: every step is a function of its input range
// only, and the parallel reductions combine counts and min/max, which are exact in any order.
#include "bvh_build.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <stdexcept>

#if SPHRAY_HAS_TBB
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>
#endif

namespace sphray::detail {
namespace {

constexpr float kInf = INFINITY;
// Bins per axis: 32 on large ranges, 8 below kFewBinsBelow spheres, where the bins' setup and
// sweep would cost more than the binning pass itself.
constexpr std::size_t kBins = 32;
constexpr std::size_t kFewBins = 16;
constexpr std::size_t kFewBinsBelow = 64;
// Below this many spheres a range is handled by one thread: the task costs more than it saves.
constexpr std::size_t kParallelMin = 16384;
// Past this depth every split is a median split, which at least halves a range: with ids
// below 2^32 the tree then stays within kBvhMaxDepth levels.
constexpr std::size_t kSahDepth = kBvhMaxDepth / 2;

using Point = std::array<float, 3>;

struct Box {
  Point lo{kInf, kInf, kInf};
  Point hi{-kInf, -kInf, -kInf};

  void grow(const Box& b) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], b.lo[k]);
      hi[k] = std::max(hi[k], b.hi[k]);
    }
  }
  void grow(const Point& p) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  bool empty() const { return !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]); }
  // Half the surface area; the SAH only compares ratios. Infinite for unbounded boxes.
  float half_area() const {
    if (empty()) return 0.0f;
    const float x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
    const float a = x * y + y * z + z * x;
    return std::isnan(a) ? kInf : a;
  }
};

bool valid_sphere(float x, float y, float z, float r) {
  return std::isfinite(x) && std::isfinite(y) && std::isfinite(z) && std::isfinite(r) && r > 0.0f;
}

// The sphere's box, widened by 2^-20 of its coordinates' magnitude: more than the rounding of
// c -+ r, and enough to hold a grazing hit that the kernel's own rounding puts just outside the
// exact sphere. An invalid sphere is never hit: its box is empty, so it never widens a parent.
Box sphere_box(float x, float y, float z, float r) {
  Box b;
  if (!valid_sphere(x, y, z, r)) return b;
  const std::array<float, 3> c{x, y, z};
  for (int k = 0; k < 3; ++k) {
    const float pad = (std::fabs(c[k]) + r) * 0x1p-20f;
    b.lo[k] = (c[k] - r) - pad;
    b.hi[k] = (c[k] + r) + pad;
  }
  return b;
}

// One sphere as the builder sees it. The build partitions an array of these in place, so every
// pass over a range reads memory in order (an array of ids into per-sphere arrays would make
// each pass a random gather, several times slower at a million spheres).
struct Prim {
  Box box;
  Point centroid;  // the centre; 0 for an invalid sphere
  std::uint32_t id;
};
using Prims = std::vector<Prim>;

template <class Body>
void parallel_for(std::size_t n, Body&& body) {
#if SPHRAY_HAS_TBB
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i)
                        body(i);
                    });
#else
  for (std::size_t i = 0; i < n; ++i)
    body(i);
#endif
}

// Combines fold(i) for i in [begin, end) with join; in parallel for large ranges. join must be
// associative and commutative and exact (counts, min, max): the result is then the same
// whatever the split.
template <class T, class Fold, class Join>
T reduce_range(std::size_t begin, std::size_t end, const T& identity, Fold&& fold, Join&& join) {
#if SPHRAY_HAS_TBB
  if (end - begin >= kParallelMin) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(begin, end, 4096), identity,
        [&](const tbb::blocked_range<std::size_t>& r, T acc) {
          for (std::size_t i = r.begin(); i < r.end(); ++i)
            fold(acc, i);
          return acc;
        },
        [&](T a, const T& b) {
          join(a, b);
          return a;
        });
  }
#else
  (void)join;  // one thread: nothing to join
#endif
  T acc = identity;
  for (std::size_t i = begin; i < end; ++i)
    fold(acc, i);
  return acc;
}

// A range of the prims that will become one child of a node.
struct Cluster {
  std::size_t begin, end;
  Box box;       // of the spheres
  Box centroid;  // of their centres

  std::size_t size() const { return end - begin; }
};

struct Bin {
  Box box;
  Box centroid;
  std::size_t count = 0;

  void grow(const Bin& b) {
    box.grow(b.box);
    centroid.grow(b.centroid);
    count += b.count;
  }
};
struct Split {
  int axis = -1;
  std::size_t bin = 0;  // spheres in bins <= bin go left
  std::size_t bins = 0;
  float scale = 0.0f;
  float origin = 0.0f;
  Bin left, right;  // what each side will hold
};

class Builder {
 public:
  Builder(Prims& prims, std::size_t width) : p_(prims), width_(width) {}

  struct Node {
    struct Child {
      Cluster cluster;
      std::unique_ptr<Node> node;  // null for a leaf
    };
    std::vector<Child> children;
  };

  Cluster cluster(std::size_t begin, std::size_t end) const {
    struct Acc {
      Box box, centroid;
    };
    const Acc acc = reduce_range(
        begin, end, Acc{},
        [&](Acc& a, std::size_t i) {
          a.box.grow(p_[i].box);
          a.centroid.grow(p_[i].centroid);
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
    return node;
  }

 private:
  void build_children(Node& node, std::size_t depth) {
#if SPHRAY_HAS_TBB
    tbb::task_group group;
    for (auto& child : node.children) {
      if (child.cluster.size() <= width_) continue;
      if (child.cluster.size() >= kParallelMin)
        group.run([this, &child, depth] { child.node = build(child.cluster, depth); });
      else
        child.node = build(child.cluster, depth);
    }
    group.wait();
#else
    for (auto& child : node.children)
      if (child.cluster.size() > width_) child.node = build(child.cluster, depth);
#endif
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
        Prim* first = p_.data() + c.begin;
        const Prim* mid = std::partition(first, p_.data() + c.end, [&](const Prim& p) {
          return (s.bins == kBins
                      ? bin_of<kBins>(p.centroid[s.axis], s.origin, s.scale)
                      : bin_of<kFewBins>(p.centroid[s.axis], s.origin, s.scale)) <= s.bin;
        });
        // The bins already hold both sides' bounds: no pass over the spheres to find them.
        const std::size_t m = c.begin + s.left.count;
        if (mid == p_.data() + m)
          return {{c.begin, m, s.left.box, s.left.centroid},
                  {m, c.end, s.right.box, s.right.centroid}};
      }
    }
    const std::size_t mid = median_split(c);
    return {cluster(c.begin, mid), cluster(mid, c.end)};
  }

  template <std::size_t Count>
  static std::size_t bin_of(float x, float origin, float scale) {
    const float b = (x - origin) * scale;
    // !(b > 0) also catches NaN.
    if (!(b > 0.0f)) return 0;
    return std::min(static_cast<std::size_t>(b), Count - 1);
  }

  // Cost of a side: its area times its leaf batches. A leaf of W spheres costs what a leaf of
  // one does, so the SAH prefers splits that fill batches.
  float side_cost(const Box& box, std::size_t count) const {
    return box.half_area() * static_cast<float>((count + width_ - 1) / width_);
  }

  template <std::size_t Count>
  Split best_sah_split(const Cluster& c) const {
    using Bins = std::array<std::array<Bin, Count>, 3>;
    std::array<float, 3> scale{}, origin{};
    for (int k = 0; k < 3; ++k) {
      origin[k] = c.centroid.lo[k];
      const float extent = c.centroid.hi[k] - c.centroid.lo[k];
      // Slightly under Count / extent, so the largest centroid lands in the last bin.
      const float s = static_cast<float>(Count) * (1.0f - 0x1p-20f) / extent;
      scale[k] = extent > 0.0f && std::isfinite(s) ? s : 0.0f;
    }
    const Bins bins = reduce_range(
        c.begin, c.end, Bins{},
        [&](Bins& b, std::size_t i) {
          const Prim& p = p_[i];
          for (int k = 0; k < 3; ++k) {
            if (scale[k] == 0.0f) continue;
            Bin& bin = b[k][bin_of<Count>(p.centroid[k], origin[k], scale[k])];
            bin.box.grow(p.box);
            bin.centroid.grow(p.centroid);
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
          best = {k, i, Count, scale[k], origin[k], left, right[i]};
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
    Prim* first = p_.data() + c.begin;
    std::nth_element(first, first + left, first + n, [&](const Prim& a, const Prim& b) {
      const float ca = a.centroid[axis], cb = b.centroid[axis];
      return ca < cb || (ca == cb && a.id < b.id);
    });
    return c.begin + left;
  }

  Prims& p_;
  std::size_t width_;
};

// Writes the built tree into the flat arrays, nodes in depth-first pre-order (a parent before
// its children, which refit relies on) and leaves' spheres in the same order.
class Flattener {
 public:
  Flattener(BvhArrays& out, const Prims& prims, SphereView src)
      : out_(out), p_(prims), src_(src), w_(out.width) {}

  static std::size_t count_nodes(const Builder::Node& n) {
    std::size_t count = 1;
    for (const auto& c : n.children)
      if (c.node) count += count_nodes(*c.node);
    return count;
  }
  static std::size_t count_batches(const Builder::Node& n, std::size_t width) {
    std::size_t count = 0;
    for (const auto& c : n.children)
      count += c.node ? count_batches(*c.node, width) : (c.cluster.size() + width - 1) / width;
    return count;
  }

  void write(const Builder::Node& node) {
    const std::size_t index = next_node_++;
    float* slots = out_.nodes.get() + index * 8 * w_;
    for (std::size_t k = 0; k < w_; ++k) {
      const Builder::Node::Child* child = k < node.children.size() ? &node.children[k] : nullptr;
      write_box(slots, k, child ? child->cluster.box : Box{});
      std::uint32_t ref = kBvhEmptySlot;
      if (child && child->node) {
        ref = static_cast<std::uint32_t>(next_node_);
        write(*child->node);
      } else if (child) {
        ref = write_leaf(child->cluster);
      }
      slots[6 * w_ + k] = std::bit_cast<float>(ref);
    }
  }

  void write_box(float* slots, std::size_t k, const Box& b) {
    for (int axis = 0; axis < 3; ++axis) {
      slots[(2 * axis) * w_ + k] = b.lo[axis];
      slots[(2 * axis + 1) * w_ + k] = b.hi[axis];
    }
  }

 private:
  std::uint32_t write_leaf(const Cluster& c) {
    const std::size_t batches = (c.size() + w_ - 1) / w_;
    const std::size_t first = next_batch_;
    next_batch_ += batches;
    for (std::size_t i = 0; i < batches * w_; ++i) {
      const std::size_t slot = first * w_ + i;
      if (c.begin + i < c.end) {
        const std::uint32_t id = p_[c.begin + i].id;
        out_.ids[slot] = id;
        out_.spheres.set(static_cast<std::uint32_t>(slot), {src_.cx[id], src_.cy[id], src_.cz[id]},
                         src_.radius[id]);
      }
    }
    return kBvhLeafBit | static_cast<std::uint32_t>((batches - 1) << kBvhLeafBatchShift) |
           static_cast<std::uint32_t>(first);
  }

  BvhArrays& out_;
  const Prims& p_;
  SphereView src_;
  std::size_t w_;
  std::size_t next_node_ = 0;
  std::size_t next_batch_ = 0;
};

Prims make_prims(SphereView v) {
  Prims p(v.count);
  parallel_for(v.count, [&](std::size_t i) {
    const Box box = sphere_box(v.cx[i], v.cy[i], v.cz[i], v.radius[i]);
    p[i] = {box, box.empty() ? Point{0.0f, 0.0f, 0.0f} : Point{v.cx[i], v.cy[i], v.cz[i]},
            static_cast<std::uint32_t>(i)};
  });
  return p;
}

void allocate(BvhArrays& out, std::size_t nodes, std::size_t batches) {
  if (batches > std::size_t{kBvhLeafFirstMask} + 1 || nodes >= kBvhEmptySlot)
    throw std::length_error("sphray::SphereBVH: too many spheres");
  const std::size_t floats = nodes * 8 * out.width;
  out.nodes.reset(
      static_cast<float*>(::operator new[](floats * sizeof(float), std::align_val_t{64})));
  std::fill_n(out.nodes.get(), floats, 0.0f);
  out.node_count = nodes;
  const std::size_t slots = batches * out.width;
  out.ids.assign(slots, kNoHit);
  out.spheres.reserve(slots);
  for (std::size_t i = 0; i < slots; ++i)
    out.spheres.add({0.0f, 0.0f, 0.0f}, 0.0f);  // never hit until a leaf fills it
}

BvhArrays build_serially_or_not(SphereView v, std::size_t width) {
  BvhArrays out;
  out.width = width;
  out.source_count = v.count;
  if (v.count == 0) return out;
  Prims prims = make_prims(v);
  Builder builder(prims, width);
  // The root is always a node, even over a single leaf, so traversal starts the same way.
  Builder::Node root;
  const Cluster all = builder.cluster(0, v.count);
  if (v.count <= width) {
    root.children.resize(1);
    root.children[0].cluster = all;
  } else {
    root = std::move(*builder.build(all, 0));
  }
  allocate(out, Flattener::count_nodes(root), Flattener::count_batches(root, width));
  Flattener(out, prims, v).write(root);
  return out;
}

}  // namespace

BvhData BvhArrays::data() const {
  BvhData d;
  d.width = width;
  d.nodes = nodes.get();
  d.node_count = node_count;
  d.spheres = spheres.view();
  d.ids = ids.data();
  d.count = source_count;
  return d;
}

std::size_t BvhArrays::memory_bytes() const {
  return node_count * 8 * width * sizeof(float) + spheres.capacity() * 4 * sizeof(float) +
         ids.capacity() * sizeof(std::uint32_t);
}

BvhArrays build_bvh(SphereView spheres, std::size_t width, unsigned threads) {
  if (spheres.count > (std::size_t{1} << 31))
    throw std::length_error("sphray::SphereBVH: more than 2^31 spheres");
#if SPHRAY_HAS_TBB
  // More threads than the machine runs would only make oneTBB warn: the tree is the same.
  const int cores = tbb::info::default_concurrency();
  const int use = threads == 0 ? cores : std::min(cores, static_cast<int>(threads));
  tbb::task_arena arena(use);
  return arena.execute([&] { return build_serially_or_not(spheres, width); });
#else
  (void)threads;
  return build_serially_or_not(spheres, width);
#endif
}

void refit_bvh(BvhArrays& tree, SphereView v) {
  if (v.count != tree.source_count)
    throw std::invalid_argument("sphray::SphereBVH::refit: the sphere count changed");
  const std::size_t w = tree.width;
  const std::size_t slots = tree.ids.size();
  parallel_for(slots, [&](std::size_t slot) {
    const std::uint32_t id = tree.ids[slot];
    if (id == kNoHit) return;
    tree.spheres.set(static_cast<std::uint32_t>(slot), {v.cx[id], v.cy[id], v.cz[id]},
                     v.radius[id]);
  });
  const SphereView s = tree.spheres.view();
  // Children come after their parent, so a reverse sweep sees every child's boxes first.
  for (std::size_t n = tree.node_count; n-- > 0;) {
    float* slots_of = tree.nodes.get() + n * 8 * w;
    for (std::size_t k = 0; k < w; ++k) {
      const std::uint32_t ref = std::bit_cast<std::uint32_t>(slots_of[6 * w + k]);
      if (ref == kBvhEmptySlot) continue;
      Box box;
      if (ref & kBvhLeafBit) {
        const std::size_t first = (ref & kBvhLeafFirstMask) * w;
        const std::size_t count = (((ref & ~kBvhLeafBit) >> kBvhLeafBatchShift) + 1) * w;
        for (std::size_t i = first; i < first + count; ++i)
          box.grow(sphere_box(s.cx[i], s.cy[i], s.cz[i], s.radius[i]));
      } else {
        const float* child = tree.nodes.get() + std::size_t{ref} * 8 * w;
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
}

}  // namespace sphray::detail
