// What a sphray_scene* points to. A handle is small and never reused: sphray_scene_release()
// frees what it holds (the spheres and the tree) and marks it released, so that a call with the
// released handle reads valid memory and reports SPHRAY_ERROR_RELEASED_SCENE instead of
// touching freed memory, for as long as the program runs, whatever scenes it creates after.
// Handles are carved from address space reserved for them alone (scene_handle.cpp); a page of
// them all released goes back to the system and reads as zeros, which is not kLive either.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <variant>

#include "sphray/sphray.h"
#include "sphray/sphray.hpp"

namespace sphray::c_api {

/// A scene's queries in precision S: brute force over the spheres' view, or the tree built from
/// it. The spheres are kept either way: surface() reads them.
template <Scalar S>
struct BasicScene {
  BasicSphereSoA<S> spheres;
  std::optional<BasicSphereBVH<S>> bvh;

  /// query(tree) when the scene has one, else query(view): the one place a C call chooses.
  template <class Query>
  decltype(auto) answer(Query&& query) const {
    return bvh ? query(*bvh) : query(spheres.view());
  }
};

/// A scene in the precision it was created in (sphray_scene_create or _create_d), for good.
struct Scene {
  std::variant<BasicScene<float>, BasicScene<double>> held;

  /// The scene in precision S, or null when it holds the other one.
  template <Scalar S>
  BasicScene<S>* in() {
    return std::get_if<BasicScene<S>>(&held);
  }
  template <Scalar S>
  const BasicScene<S>* in() const {
    return std::get_if<BasicScene<S>>(&held);
  }
  /// use(scene) with the scene in its precision.
  template <class Use>
  decltype(auto) visit(Use&& use) {
    return std::visit(std::forward<Use>(use), held);
  }
  template <class Use>
  decltype(auto) visit(Use&& use) const {
    return std::visit(std::forward<Use>(use), held);
  }
};

}  // namespace sphray::c_api

struct sphray_scene {
  // kLive while it holds a scene; kReleased after, or 0 once its page went back to the system:
  // a cheap check against stale handles (and, when the pointer is not a handle at all, a
  // likely mismatch rather than a silent misuse).
  static constexpr std::uint32_t kLive = 0x53504852u;      // "SPHR"
  static constexpr std::uint32_t kReleased = 0x44454144u;  // "DEAD"

  std::uint32_t magic = kReleased;
  sphray::c_api::Scene* scene = nullptr;
};

namespace sphray::c_api {

/// A new handle holding scene (taken over). Throws std::bad_alloc (and then deletes scene).
sphray_scene* adopt(Scene* scene);

/// Deletes the handle's scene and marks it released, for good.
void retire(sphray_scene* handle) noexcept;

}  // namespace sphray::c_api
