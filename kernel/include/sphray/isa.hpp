// Instruction sets: which one the queries use, and which ones this machine runs.
//
// The queries in query.hpp go through the kernel of the best instruction set this CPU and its
// operating system support, chosen once on first use. The environment variable SPHRAY_ISA
// (scalar, sse4.2, avx2, avx512, neon) forces one; if this machine cannot run it, a message
// on stderr says so and the best one is used instead.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "sphray/api.h"
#include "sphray/ray.hpp"
#include "sphray/spheres.hpp"

namespace sphray {

enum class Isa { scalar, sse4_2, avx2, avx512, neon };

/// "scalar", "sse4.2", "avx2", "avx512", "neon": the names SPHRAY_ISA takes.
SPHRAY_API std::string_view isa_name(Isa isa);
/// The Isa a name stands for, or nothing if it names none.
SPHRAY_API std::optional<Isa> parse_isa(std::string_view name);
/// The number of spheres one batch of this instruction set holds (1 for scalar).
SPHRAY_API std::size_t isa_width(Isa isa);

/// The instruction sets this build has and this machine can run, best first.
SPHRAY_API std::span<const Isa> supported_isas();

/// What a SPHRAY_ISA value (nullptr: unset) selects on this machine, and a message to print
/// if it could not be honoured (empty otherwise). Pure: reads no environment.
struct IsaChoice {
  Isa isa;
  std::string message;
};
SPHRAY_API IsaChoice choose_isa(const char* requested);

/// The instruction set the queries in query.hpp use (SPHRAY_ISA read once, on first use).
SPHRAY_API Isa active_isa();

/// The instruction set a SphereBVH over sphere_count spheres built without one is laid out for:
/// SPHRAY_ISA's when it is set and can run here, otherwise the one that walks trees of that
/// size fastest on this CPU, by a rule on its vendor and family (on AMD Zen 4, which runs
/// AVX-512 as two 256-bit halves: avx2 below 1024 spheres, avx512 from there). The CPU and
/// SPHRAY_ISA are read once, on first use.
SPHRAY_API Isa bvh_isa(std::size_t sphere_count);
/// bvh_isa for a tree of many spheres, at or above every size the rule distinguishes.
SPHRAY_API Isa bvh_isa();
}  // namespace sphray
