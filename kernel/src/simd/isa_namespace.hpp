// The namespace of code compiled once per instruction set (Embree's "isa" namespaces).
//
// A per-ISA unit (dispatch/isa_*.cpp) is built with SPHRAY_ISA_NAMESPACE set to its instruction
// set's name (CMakeLists.txt), every other unit with "baseline". Headers whose code such a unit
// compiles (simd/, brute/sphere_lanes.hpp and brute_force.hpp, the walk's headers in bvh/,
// dispatch/entry_points.hpp) put it in sphray::detail::SPHRAY_ISA_NAMESPACE: an inline function
// there is a different symbol in every unit, so the linker can never keep one unit's AVX-512
// copy for another unit's callers. What they call outside it must still be templated on the
// xsimd architecture (xsimd) or a builtin: a public header's inline function, or the standard
// library's, is one symbol for all units. tests/kernel/isa_symbols.sh checks the library.
#pragma once

#ifndef SPHRAY_ISA_NAMESPACE
#define SPHRAY_ISA_NAMESPACE baseline
#endif
