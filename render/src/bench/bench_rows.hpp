// The rows `sphray bench` times: each a way to turn rays into hits on a scene's spheres.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "sphray/sphray.hpp"

namespace sphray::render::bench {

/// Traces rays into hits (hits.size() == rays.size()); called on several threads at once, each
/// with its own part of the rays.
using Trace = std::function<void(std::span<const Ray> rays, std::span<Hit> hits)>;

struct Row {
  std::string name;  // "avx2 tree", "embree rtcIntersect8"
  /// Tests every sphere for every ray: traces RaySet::brute_rays, fewer on large scenes.
  bool brute_force = false;
  /// sphray's rows return the scalar reference's bits; another library's only agree within
  /// rounding (and may break a tie on t the other way).
  bool exact = true;
  /// What sphray::intersect itself takes on this machine for this scene.
  bool dispatched = false;
  /// Readies the row for the spheres outside the timed passes (a tree's build, say).
  std::function<Trace(SphereView spheres)> prepare;
  /// Why the row is not timed on this scene or machine ("brute force is timed up to ..."), or
  /// empty: a skipped row is listed with its reason, never left out silently.
  std::string skipped = {};
};

/// Brute force is timed up to this many spheres: beyond, it is slower than the tree by orders
/// of magnitude, and a pass over a useful number of rays would take minutes.
inline constexpr std::size_t kBruteForceUpTo = 4096;

/// The scalar reference and each instruction set's brute force per ray and with the rays across
/// its lanes, and the stream call on the spheres (all skipped on large scenes); each
/// instruction set's tree per ray and its stream call.
std::vector<Row> sphray_rows(std::size_t sphere_count);

/// Intel Embree 3's rtcIntersect1, 8 and 16 where this build has Embree (8 and 16 skipped where
/// this Embree has no native packets of that width); none otherwise.
std::vector<Row> embree_rows();
/// The instruction sets this machine runs, best first, separated by spaces.
std::string supported_isa_list();

/// "Embree 3.x.y", or empty without Embree.
std::string embree_version();

}  // namespace sphray::render::bench
