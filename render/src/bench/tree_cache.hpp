// One tree of a scene's spheres, shared by the rows of `sphray bench` that time it: built by
// the first row that asks, outside the timed passes, and handed on to the next.
#pragma once

#include <memory>
#include <optional>

#include "sphray/sphray.hpp"

namespace sphray::render::bench {

class TreeCache {
 public:
  /// A cache of trees laid out for isa; nothing: the default tree (bvh_isa of the scene).
  explicit TreeCache(std::optional<Isa> isa = std::nullopt) : isa_(isa) {}

  /// The tree of spheres, built on the first call; a view of other spheres builds anew.
  std::shared_ptr<const SphereBVH> get(SphereView spheres) {
    if (!tree_ || built_from_ != spheres.cx) {
      tree_.reset();  // the old tree goes before the new one is built
      tree_ = isa_ ? std::make_shared<const SphereBVH>(spheres, *isa_)
                   : std::make_shared<const SphereBVH>(spheres);
      built_from_ = spheres.cx;
    }
    return tree_;
  }

  /// get(), and the cache lets go of the tree: the last row to use it takes it, so that no
  /// more than one tree of a large scene is alive at a time.
  std::shared_ptr<const SphereBVH> take(SphereView spheres) {
    std::shared_ptr<const SphereBVH> tree = get(spheres);
    tree_.reset();
    return tree;
  }

  std::optional<Isa> isa() const { return isa_; }

 private:
  std::optional<Isa> isa_;
  const float* built_from_ = nullptr;
  std::shared_ptr<const SphereBVH> tree_;
};

}  // namespace sphray::render::bench
