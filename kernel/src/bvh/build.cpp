// Building a tree: the builder's nodes (builder.hpp) flattened into the traversal's layout,
// every leaf its own aligned batch of sphere slots (docs/bvh.md, "Layout").
#include "bvh/build.hpp"

#include <algorithm>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "bvh/builder.hpp"
#include "bvh/parallel.hpp"
#include "bvh/prim.hpp"

#if SPHRAY_HAS_TBB
#include <tbb/info.h>
#include <tbb/task_arena.h>
#endif

namespace sphray::detail {
namespace {

// Where leaf k's spheres go: prims [begin, begin + count) to the slots from k * width on.
// 8 bytes a leaf, as the list is alive with the output's slots (the build's peak, issue 34);
// a tree has fewer than 2^31 spheres.
struct LeafPlace {
  std::uint32_t begin, count;
};

// Writes the built tree's nodes in depth-first pre-order (a parent before its children, which
// refit relies on), and gives every leaf its own batch of width sphere slots: its reference is
// its first slot, a multiple of the width, plus its count - 1. An aligned leaf is read as one
// batch without a cache-line split, and the lanes past its count hold never-hit padding, not
// the next leaf's spheres (whose extra hits only made the closest-hit fold longer).
template <Scalar S>
class Flattener {
 public:
  explicit Flattener(BasicBvhArrays<S>& out) : out_(out), w_(out.width) {}

  std::vector<LeafPlace> leaves;
  std::size_t slots_used = 0;  // leaves.size() * width

  void write(const Builder::Node& node, std::size_t index) {
    const NodeView<float> view(out_.nodes.get(), index, w_);
    std::size_t next = index + 1;
    for (std::size_t k = 0; k < w_; ++k) {
      const Builder::Node::Child* child = k < node.children.size() ? &node.children[k] : nullptr;
      ChildRef ref = ChildRef::empty();
      if (child && child->node) {
        ref = ChildRef::node(next);
        write(*child->node, next);
        next += child->node->subtree_nodes;
      } else if (child) {
        const std::size_t count = child->size();
        ref = ChildRef::leaf(slots_used, count);
        leaves.push_back(
            {static_cast<std::uint32_t>(child->begin), static_cast<std::uint32_t>(count)});
        slots_used += w_;
      }
      write_box(view, k, child ? child->box : Box{});
      view.set_ref(k, ref);
    }
  }

 private:
  BasicBvhArrays<S>& out_;
  std::size_t w_;
};

// Double spheres go in as the float records that hold them (Prim::make for doubles).
template <Scalar S>
Prims make_prims(BasicSphereView<S> v) {
  Prims p(v.count);
  parallel_for(v.count, kBlock, [&](std::size_t i) {
    p[i] = Prim::make(v.cx[i], v.cy[i], v.cz[i], v.radius[i]);
    p.ids[i] = static_cast<std::uint32_t>(i);
  });
  return p;
}

template <class T>
AlignedArray<T> allocate(std::size_t n) {
  AlignedArray<T> array(static_cast<T*>(::operator new[](n * sizeof(T), std::align_val_t{64})));
  prefer_huge_pages(array.get(), n * sizeof(T));
  return array;
}

// The zeroed nodes of a tree of nodes nodes.
template <Scalar S>
void allocate_nodes(BasicBvhArrays<S>& out, std::size_t nodes) {
  if (nodes >= ChildRef::kEmptyBits) throw std::length_error("sphray::SphereBVH: too many spheres");
  out.nodes = allocate<float>(node_floats(nodes, out.width));
  std::fill_n(out.nodes.get(), node_floats(nodes, out.width), 0.0f);
  out.node_count = nodes;
}

// The sphere slots, rounded to 16 so that each of the four arrays starts on a cache
// line. Not written here: write_leaves writes every slot, in order, so that a slot's page is
// first touched when it is filled.
template <Scalar S>
void allocate_slots(BasicBvhArrays<S>& out, std::size_t slots) {
  out.slots = (slots + 15) / 16 * 16;
  if (out.slots >= kBvhLeafBit) throw std::length_error("sphray::SphereBVH: too many spheres");
  out.spheres = allocate<S>(4 * out.slots);
  out.ids = allocate<std::uint32_t>(out.slots);
}

// Slots [first, first + count) as never hit: centre 0, radius 0, id kNoHit.
template <Scalar S>
void write_padding(BasicBvhArrays<S>& out, std::size_t first, std::size_t count) {
  S* x = out.spheres.get() + first;
  for (std::size_t row = 0; row < 4; ++row)
    std::fill_n(x + row * out.slots, count, S{0});
  std::fill_n(out.ids.get() + first, count, kNoHit);
}

// Leaf k's spheres and ids to its slots, then never-hit padding to the width; an invalid
// sphere as centre 0 and radius 0, which the kernel never hits either. Float spheres come from
// the records, read in order; double ones from the view, as the records hold only their float
// enclosures.
template <Scalar S>
void write_leaf(BasicBvhArrays<S>& out, BasicSphereView<S> v, const Prims& prims,
                const LeafPlace& leaf, std::size_t k) {
  S* x = out.spheres.get();
  S *y = x + out.slots, *z = y + out.slots, *r = z + out.slots;
  const std::size_t first = k * out.width;
  for (std::size_t j = 0; j < leaf.count; ++j) {
    const Prim& p = prims[leaf.begin + j];
    const std::uint32_t id = prims.ids[leaf.begin + j];
    const bool valid = p.sphere[3] >= 0.0f;  // an invalid sphere's radius is -inf (prim.hpp)
    if constexpr (std::is_same_v<S, float>) {
      x[first + j] = p.sphere[0];
      y[first + j] = p.sphere[1];
      z[first + j] = p.sphere[2];
      r[first + j] = valid ? p.sphere[3] : 0.0f;
    } else {
      x[first + j] = valid ? v.cx[id] : 0.0;
      y[first + j] = valid ? v.cy[id] : 0.0;
      z[first + j] = valid ? v.cz[id] : 0.0;
      r[first + j] = valid ? v.radius[id] : 0.0;
    }
    out.ids[first + j] = id;
  }
  write_padding(out, first + leaf.count, out.width - leaf.count);
}

// Every slot of the tree, from the records, which hold the leaves' spheres in leaf order. The
// records' pages go back to the system a stretch at a time as they are read, so the slots take
// their place rather than adding to the build's peak memory (issue 34).
template <Scalar S>
void write_leaves(BasicBvhArrays<S>& out, BasicSphereView<S> v, Prims& prims,
                  const std::vector<LeafPlace>& leaves) {
  constexpr std::size_t kStretch = std::size_t{1} << 16;  // leaves: about 1M spheres
  for (std::size_t begin = 0; begin < leaves.size(); begin += kStretch) {
    const std::size_t end = std::min(begin + kStretch, leaves.size());
    parallel_for(end - begin, kBlock / 16,
                 [&](std::size_t k) { write_leaf(out, v, prims, leaves[begin + k], begin + k); });
    const std::size_t from = leaves[begin].begin;
    const std::size_t to = end < leaves.size() ? leaves[end].begin : prims.size;
    release_pages(&prims[from], (to - from) * sizeof(Prim));
    release_pages(&prims.ids[from], (to - from) * sizeof(std::uint32_t));
  }
  const std::size_t used = leaves.size() * out.width;
  write_padding(out, used, out.slots - used);
}

// The most spheres a flat tree holds: kBvhBruteForceLeaves full leaves, as many as the root
// has children.
std::size_t flat_up_to(std::size_t width) {
  return width * std::min(width, kBvhBruteForceLeaves);
}

// The builder's tree over prims, which it permutes into leaf order, in place.
Builder::Node build_nodes(Prims& prims, std::size_t width, std::size_t parallel_min,
                          ProgressCount& progress, bool flat) {
  Builder builder(prims, width, parallel_min, progress);
  const std::size_t n = prims.size;
  // The root is always a node, even over a single leaf, so traversal starts the same way.
  if (!flat) return std::move(*builder.build(builder.cluster(0, n), 0));
  // Few enough spheres that the tree is read as brute force (bvh_data.hpp,
  // kBvhBruteForceLeaves): full leaves in id order under the root, the batches brute force
  // reads, rather than the builder's leaves, whose padding would add batches.
  Builder::Node root;
  for (std::size_t begin = 0; begin < n; begin += width)
    root.children.emplace_back(builder.cluster(begin, std::min(n, begin + width)));
  return root;
}

template <Scalar S>
BasicBvhArrays<S> build_here(BasicSphereView<S> v, std::size_t width, std::size_t parallel_min,
                             ProgressCount& progress) {
  BasicBvhArrays<S> out;
  out.width = width;
  out.source_count = v.count;
  if (v.count == 0) return out;
  out.flat = v.count <= flat_up_to(width);
  Prims prims = make_prims(v);
  Flattener<S> flat(out);
  {
    // The builder's nodes go before the slots, the largest output array, are allocated.
    const Builder::Node root = build_nodes(prims, width, parallel_min, progress, out.flat);
    allocate_nodes(out, root.subtree_nodes);
    flat.write(root, 0);
  }
  allocate_slots(out, flat.slots_used);
  write_leaves(out, v, prims, flat.leaves);
  out.leaf_overlap = measure_leaf_overlap(out);
  return out;
}

}  // namespace

template <Scalar S>
BasicBvhData<S> BasicBvhArrays<S>::data() const {
  BasicBvhData<S> d;
  d.width = width;
  d.nodes = nodes.get();
  d.node_count = node_count;
  if (slots != 0) {
    const S* x = spheres.get();
    d.spheres = {x, x + slots, x + 2 * slots, x + 3 * slots, slots, slots, masks.get()};
  }
  d.ids = ids.get();
  d.flat = flat;
  d.count = source_count;
  d.memory_bytes = memory_bytes();
  d.leaf_overlap = leaf_overlap;
  return d;
}

template <Scalar S>
std::size_t BasicBvhArrays<S>::memory_bytes() const {
  return node_floats(node_count, width) * sizeof(float) +
         slots * (4 * sizeof(S) + sizeof(std::uint32_t)) +
         (masks ? slots * sizeof(std::uint32_t) : 0);
}

template <Scalar S>
BasicBvhArrays<S> build_bvh(BasicSphereView<S> spheres, std::size_t width,
                            const BvhBuildOptions& options, const BuildProgress& report) {
  if (spheres.count > (std::size_t{1} << 31))
    throw std::length_error("sphray::SphereBVH: more than 2^31 spheres");
  ProgressCount progress(report, spheres.count);
#if SPHRAY_HAS_TBB
  // More threads than the machine runs would only make oneTBB warn: the tree is the same.
  const int cores = tbb::info::default_concurrency();
  const int use = options.threads == 0 ? cores : std::min(cores, static_cast<int>(options.threads));
  tbb::task_arena arena(use);
  BasicBvhArrays<S> tree =
      arena.execute([&] { return build_here(spheres, width, options.parallel_min, progress); });
#else
  BasicBvhArrays<S> tree = build_here(spheres, width, options.parallel_min, progress);
#endif
  progress.done();
  copy_masks(tree, spheres);
  return tree;
}

template struct BasicBvhArrays<float>;
template struct BasicBvhArrays<double>;
template BasicBvhArrays<float> build_bvh(SphereView, std::size_t, const BvhBuildOptions&,
                                         const BuildProgress&);
template BasicBvhArrays<double> build_bvh(SphereViewd, std::size_t, const BvhBuildOptions&,
                                          const BuildProgress&);

}  // namespace sphray::detail
