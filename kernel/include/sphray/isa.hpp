// Instruction sets: which one the queries use, and each one's entry points by name.
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

#include "sphray/ray.hpp"
#include "sphray/spheres.hpp"

namespace sphray {

namespace detail {
struct BvhData;  // bvh.hpp
}  // namespace detail

enum class Isa { scalar, sse4_2, avx2, avx512, neon };

/// "scalar", "sse4.2", "avx2", "avx512", "neon": the names SPHRAY_ISA takes.
std::string_view isa_name(Isa isa);
/// The Isa a name stands for, or nothing if it names none.
std::optional<Isa> parse_isa(std::string_view name);
/// The number of spheres one batch of this instruction set holds (1 for scalar).
std::size_t isa_width(Isa isa);

/// The entry points of one instruction set's kernel. Same contract as query.hpp.
struct Kernel {
  Isa isa;
  std::size_t width;
  Hit (*intersect)(SphereView spheres, const Ray& ray);
  bool (*occluded)(SphereView spheres, const Ray& ray);
  /// hits[i] = intersect(spheres, rays[i]) for i < count.
  void (*intersect_stream)(SphereView spheres, const Ray* rays, Hit* hits, std::size_t count);
  /// The SphereBVH entries (bvh.hpp) for trees of bvh_width children per node and spheres per
  /// leaf batch.
  std::size_t bvh_width;
  Hit (*bvh_intersect)(const detail::BvhData& bvh, const Ray& ray);
  bool (*bvh_occluded)(const detail::BvhData& bvh, const Ray& ray);
  void (*bvh_intersect_stream)(const detail::BvhData& bvh, const Ray* rays, Hit* hits,
                               std::size_t count);
};

/// The kernel for isa, or nullptr if this build lacks it or this machine cannot run it.
const Kernel* find_kernel(Isa isa);
/// The instruction sets this build has and this machine can run, best first.
std::span<const Isa> supported_isas();

/// What a SPHRAY_ISA value (nullptr: unset) selects on this machine, and a message to print
/// if it could not be honoured (empty otherwise). Pure: reads no environment.
struct IsaChoice {
  Isa isa;
  std::string message;
};
IsaChoice choose_isa(const char* requested);

/// The instruction set the queries in query.hpp use (SPHRAY_ISA read once, on first use).
Isa active_isa();
const Kernel& active_kernel();
/// The kernel the brute-force queries in query.hpp use for a view of sphere_count spheres:
/// active_kernel(), except that a view too small to fill two thirds of its batch goes to the
/// widest narrower instruction set it does fill (a batch costs its full width whatever it
/// holds), and a view of fewer than two spheres to the scalar kernel. All of them return the same
/// hits, within the kernel's tolerance.
const Kernel& kernel_for_size(std::size_t sphere_count);

}  // namespace sphray
