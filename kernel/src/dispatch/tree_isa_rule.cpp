#include "dispatch/tree_isa_rule.hpp"

#include <algorithm>
#include <array>

namespace sphray::detail {
namespace {

struct TreeIsaRule {
  CpuVendor vendor;
  unsigned family;
  std::size_t from_spheres;  // the line holds for trees of at least this many spheres
  Isa isa;
};

// Lines per CPU family measured with `sphray bench` (the avx2 and avx512 tree and stream rows
// side by side, camera and random rays; docs/decisions.md, "The tree's instruction set, small
// trees and `sphray bench` (issue 19)"); for a family, the last line whose size a tree reaches
// holds. A family without a line takes the widest instruction set, as the brute force does.
// - AMD family 0x1A (Zen 5, EPYC 9005): the 16-wide tree walks the random scenes of 4096 to
//   1048576 spheres faster than the 8-wide one and only rtiow-final slower, a property of that
//   scene: avx512, the widest, at every size.
// - AMD family 0x19 (Zen 4, EPYC 9004, which runs a 512-bit instruction as two 256-bit
//   halves): the 8-wide tree is faster on rtiow-final (486 spheres) and random:512, per ray and
//   in the stream; at 1024 spheres the two are even, and from 2048 on the 16-wide one wins,
//   most on the stream's packets: avx2 below 1024 spheres, avx512 from there.
constexpr std::array kTreeIsaRules = {
    TreeIsaRule{CpuVendor::amd, 0x1a, 0, Isa::avx512},
    TreeIsaRule{CpuVendor::amd, 0x19, 0, Isa::avx2},
    TreeIsaRule{CpuVendor::amd, 0x19, 1024, Isa::avx512},
};

bool has(std::span<const Isa> available, Isa isa) {
  return std::find(available.begin(), available.end(), isa) != available.end();
}

}  // namespace

Isa tree_isa_for(const CpuIdentity& cpu, std::span<const Isa> available, std::size_t sphere_count) {
  Isa chosen = available.front();
  for (const TreeIsaRule& rule : kTreeIsaRules)
    if (rule.vendor == cpu.vendor && rule.family == cpu.family &&
        sphere_count >= rule.from_spheres && has(available, rule.isa))
      chosen = rule.isa;
  return chosen;
}

}  // namespace sphray::detail
