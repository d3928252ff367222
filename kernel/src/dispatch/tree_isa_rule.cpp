#include "dispatch/tree_isa_rule.hpp"

#include <algorithm>
#include <array>

namespace sphray::detail {
namespace {

struct TreeIsaRule {
  CpuVendor vendor;
  unsigned family;
  Isa isa;
};

// One line per CPU family measured with `sphray bench` (the avx2 and avx512 tree rows side by
// side; docs/decisions.md, "The tree's instruction set per CPU"). A family without a line takes
// the widest instruction set, as the brute force does.
// - AMD family 0x1A (Zen 5, EPYC 9005): the 16-wide tree walks random scenes of 4096 to
//   1048576 spheres 1-40% faster than the 8-wide one, rtiow-final 2-14% slower: avx512, the
//   widest.
// AMD family 0x19 (Zen 4, which runs a 512-bit instruction as two 256-bit halves) is not
// measured yet; its line belongs here once it is.
constexpr std::array kTreeIsaRules = {
    TreeIsaRule{CpuVendor::amd, 0x1a, Isa::avx512},
};

bool has(std::span<const Isa> available, Isa isa) {
  return std::find(available.begin(), available.end(), isa) != available.end();
}

}  // namespace

Isa tree_isa_for(const CpuIdentity& cpu, std::span<const Isa> available) {
  for (const TreeIsaRule& rule : kTreeIsaRules)
    if (rule.vendor == cpu.vendor && rule.family == cpu.family && has(available, rule.isa))
      return rule.isa;
  return available.front();
}

}  // namespace sphray::detail
