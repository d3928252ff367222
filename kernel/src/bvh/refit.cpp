// Refit: the moved spheres copied into the tree's leaf order and every box recomputed
// bottom-up, the tree's shape kept; and the leaf overlap, measured after a build or a refit.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "bvh/build.hpp"
#include "bvh/parallel.hpp"
#include "bvh/prim.hpp"

namespace sphray::detail {
namespace {

// Copies sphere ids[slot] of v into every slot that holds one, for refit.
template <Scalar S>
void copy_spheres(BasicBvhArrays<S>& out, BasicSphereView<S> v) {
  S* x = out.spheres.get();
  S *y = x + out.slots, *z = y + out.slots, *r = z + out.slots;
  parallel_for(out.slots, kBlock, [&](std::size_t slot) {
    const std::uint32_t id = out.ids[slot];
    if (id == kNoHit) return;
    x[slot] = v.cx[id];
    y[slot] = v.cy[id];
    z[slot] = v.cz[id];
    r[slot] = v.radius[id];
  });
}

}  // namespace

// The leaf boxes' summed volume over the root box's (BvhArrays::leaf_overlap), from the
// written nodes: one pass over them, after a build or a refit. Every leaf box lies in the root
// box, so the ratio is at most the leaf count; the clamp only keeps the cast to float defined
// whatever the input.
template <Scalar S>
float measure_leaf_overlap(const BasicBvhArrays<S>& tree) {
  const std::size_t w = tree.width;
  double leaf_volume = 0.0;
  Box root;
  for (std::size_t n = 0; n < tree.node_count; ++n) {
    const NodeView<const float> node(tree.nodes.get(), n, w);
    for (std::size_t k = 0; k < w; ++k) {
      const ChildRef ref = node.ref(k);
      if (ref.is_empty() || (n != 0 && !ref.is_leaf())) continue;
      const Box box = read_box(node, k);
      if (n == 0) root.grow(box);
      if (ref.is_leaf()) leaf_volume += box.volume();
    }
  }
  const double overlap = leaf_volume / root.volume();
  return std::isfinite(overlap) ? static_cast<float>(std::min(overlap, 1e30)) : 0.0f;
}

template <Scalar S>
void copy_masks(BasicBvhArrays<S>& tree, BasicSphereView<S> v) {
  if (v.mask == nullptr || tree.slots == 0) {
    tree.masks.reset();
    return;
  }
  if (!tree.masks)
    tree.masks.reset(static_cast<std::uint32_t*>(
        ::operator new[](tree.slots * sizeof(std::uint32_t), std::align_val_t{64})));
  for (std::size_t slot = 0; slot < tree.slots; ++slot) {
    const std::uint32_t id = tree.ids[slot];
    tree.masks[slot] = id == kNoHit ? 0u : v.mask[id];
  }
}

template <Scalar S>
void refit_bvh(BasicBvhArrays<S>& tree, BasicSphereView<S> v) {
  if (v.count != tree.source_count)
    throw std::invalid_argument("sphray::SphereBVH::refit: the sphere count changed");
  if (tree.node_count == 0) return;
  copy_spheres(tree, v);
  copy_masks(tree, v);
  const BasicBvhData<S> d = tree.data();
  const std::size_t w = tree.width;
  // Children come after their parent, so a reverse sweep sees every child's boxes first.
  for (std::size_t n = tree.node_count; n-- > 0;) {
    const NodeView<float> node(tree.nodes.get(), n, w);
    for (std::size_t k = 0; k < w; ++k) {
      const ChildRef ref = node.ref(k);
      if (ref.is_empty()) continue;
      Box box;
      if (ref.is_leaf()) {
        for (std::size_t i = ref.first(w); i < ref.first(w) + ref.count(w); ++i)
          box.grow(
              sphere_box(d.spheres.cx[i], d.spheres.cy[i], d.spheres.cz[i], d.spheres.radius[i]));
      } else {
        const NodeView<const float> child(tree.nodes.get(), ref.node_index(), w);
        for (std::size_t j = 0; j < w; ++j)
          for (int axis = 0; axis < 3; ++axis) {
            box.lo[axis] = std::min(box.lo[axis], child.lo(axis, j));
            box.hi[axis] = std::max(box.hi[axis], child.hi(axis, j));
          }
      }
      write_box(node, k, box);
    }
  }
  tree.leaf_overlap = measure_leaf_overlap(tree);
}

template float measure_leaf_overlap(const BasicBvhArrays<float>&);
template float measure_leaf_overlap(const BasicBvhArrays<double>&);
template void copy_masks(BasicBvhArrays<float>&, SphereView);
template void copy_masks(BasicBvhArrays<double>&, SphereViewd);
template void refit_bvh(BasicBvhArrays<float>&, SphereView);
template void refit_bvh(BasicBvhArrays<double>&, SphereViewd);

}  // namespace sphray::detail
