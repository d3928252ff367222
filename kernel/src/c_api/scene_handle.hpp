// What a sphray_scene* points to. A handle is small and never reused: sphray_scene_release()
// frees what it holds (the spheres and the tree) and marks it released, so that a call with the
// released handle reads valid memory and reports SPHRAY_ERROR_RELEASED_SCENE instead of
// touching freed memory, for as long as the program runs, whatever scenes it creates after.
// Handles are carved from address space reserved for them alone (scene_handle.cpp); a page of
// them all released goes back to the system and reads as zeros, which is not kLive either.
#pragma once

#include <cstdint>
#include <optional>

#include "sphray/sphray.h"
#include "sphray/sphray.hpp"

namespace sphray::c_api {

/// A scene's queries: brute force over the spheres' view, or the tree built from it. The
/// spheres are kept either way: surface() reads them.
struct Scene {
  SphereSoA spheres;
  std::optional<SphereBVH> bvh;

  /// query(tree) when the scene has one, else query(view): the one place a C call chooses.
  template <class Query>
  decltype(auto) answer(Query&& query) const {
    return bvh ? query(*bvh) : query(spheres.view());
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
