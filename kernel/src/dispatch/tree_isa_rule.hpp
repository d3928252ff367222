// Which instruction set a tree is laid out for and walked with when none is asked for: a rule by
// the CPU's vendor and family, written down from measurements, never a timing at start-up
// (which a loaded machine would answer differently from run to run, and every process would pay
// for). SPHRAY_ISA overrides it (dispatch.cpp).
#pragma once

#include <cstddef>
#include <span>

#include "dispatch/cpu.hpp"
#include "sphray/isa.hpp"

namespace sphray::detail {

/// The instruction set of a tree over sphere_count spheres on cpu, among available (the
/// supported ones, best first, never empty): the one kTreeIsaRules names for the CPU's vendor,
/// family and that size when it is available, otherwise the best one.
Isa tree_isa_for(const CpuIdentity& cpu, std::span<const Isa> available, std::size_t sphere_count);

}  // namespace sphray::detail
