// Run-time choice of the instruction set: the table of kernels this build has, filtered by what
// the CPU and OS support, and SPHRAY_ISA.
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>

#include "dispatch/cpu.hpp"
#include "dispatch/entry_table.hpp"
#include "dispatch/query_plan.hpp"
#include "dispatch/tree_isa_rule.hpp"
#include "sphray/isa.hpp"

namespace sphray {
namespace {

using detail::EntryTable;
using detail::find_entries;

constexpr std::array<std::string_view, 5> kNames = {"scalar", "sse4.2", "avx2", "avx512", "neon"};

// Every kernel this build has, best first.
constexpr std::array kBuilt = {
#if SPHRAY_HAS_AVX512
    &detail::kAvx512Entries,
#endif
#if SPHRAY_HAS_AVX2
    &detail::kAvx2Entries,
#endif
#if SPHRAY_HAS_SSE4_2
    &detail::kSse42Entries,
#endif
#if SPHRAY_HAS_NEON
    &detail::kNeonEntries,
#endif
    &detail::kScalarEntries,
};

bool cpu_runs(Isa isa, const detail::CpuFeatures& cpu) {
  switch (isa) {
    case Isa::scalar:
      return true;
    case Isa::sse4_2:
      return cpu.sse4_2;
    case Isa::avx2:
      return cpu.avx2_fma;
    case Isa::avx512:
      return cpu.avx512f;
    case Isa::neon:
      return cpu.neon;
  }
  return false;
}

// The supported kernels, best first; computed once. Immutable afterwards, so concurrent reads
// need no lock (and C++ makes the initialisation itself thread-safe).
struct Supported {
  std::array<Isa, kBuilt.size()> isas{};
  std::array<const EntryTable*, kBuilt.size()> kernels{};
  std::size_t count = 0;

  Supported() {
    const detail::CpuFeatures cpu = detail::detect_cpu();
    for (const EntryTable* k : kBuilt) {
      if (!cpu_runs(k->isa, cpu)) continue;
      isas[count] = k->isa;
      kernels[count++] = k;
    }
  }
};

const Supported& supported() {
  static const Supported s;
  return s;
}

// The active kernel, and for views too small to fill its batches, a narrower one; and the
// kernel of trees built without an instruction set: SPHRAY_ISA's when it is honoured, otherwise
// the rule by CPU (tree_isa_rule.hpp).
struct Choice {
  static constexpr std::size_t kSmall = 32;  // views below this many spheres may go narrower
  const EntryTable* active = nullptr;
  bool tree_forced = false;  // SPHRAY_ISA is honoured: trees take it too, at every size
  detail::CpuIdentity cpu{};
  std::array<const EntryTable*, kSmall> by_count{};

  Choice() {
    const char* requested = std::getenv("SPHRAY_ISA");
    const IsaChoice choice = choose_isa(requested);
    if (!choice.message.empty()) std::fprintf(stderr, "%s\n", choice.message.c_str());
    active = find_entries(choice.isa);
    tree_forced = requested != nullptr && *requested != '\0' && choice.message.empty();
    cpu = detail::identify_cpu();
    for (std::size_t n = 0; n < kSmall; ++n)
      by_count[n] = narrowest_fit(n);
  }

  // A batch costs its full width whatever it holds, so a kernel pays off over the narrower ones
  // only once the view fills most of one batch, and a single sphere is fastest in the scalar
  // loop (docs/kernel.md, "The SIMD algorithm"; docs/performance.md, "Rays per second"). The
  // widest kernel no wider than the active one whose width is at most max(4, 1.5 n), or the
  // scalar one below kScalarBelow spheres.
  const EntryTable* narrowest_fit(std::size_t n) const {
    const std::size_t widest = detail::SPHRAY_ISA_NAMESPACE::QueryPlan::scalar(n)
                                   ? 1
                                   : std::max<std::size_t>(4, 3 * n / 2);
    for (const EntryTable* k : supported().kernels)
      if (k != nullptr && k->width <= active->width && k->width <= widest) return k;
    return active;
  }
};

const Choice& choice() {
  static const Choice c;
  return c;
}
}  // namespace

std::string_view isa_name(Isa isa) {
  return kNames.at(static_cast<std::size_t>(isa));
}

std::optional<Isa> parse_isa(std::string_view name) {
  for (std::size_t i = 0; i < kNames.size(); ++i)
    if (kNames[i] == name) return static_cast<Isa>(i);
  return std::nullopt;
}

std::size_t isa_width(Isa isa) {
  switch (isa) {
    case Isa::scalar:
      return 1;
    case Isa::sse4_2:
      return 4;
    case Isa::avx2:
      return 8;
    case Isa::avx512:
      return 16;
    case Isa::neon:
      return 4;
  }
  return 1;
}

namespace detail {

const EntryTable* find_entries(Isa isa) {
  const Supported& s = supported();
  for (std::size_t i = 0; i < s.count; ++i)
    if (s.isas[i] == isa) return s.kernels[i];
  return nullptr;
}

}  // namespace detail

std::span<const Isa> supported_isas() {
  const Supported& s = supported();
  return {s.isas.data(), s.count};
}

IsaChoice choose_isa(const char* requested) {
  const Isa best = supported_isas().front();
  if (requested == nullptr || *requested == '\0') return {best, {}};
  const std::string best_name(isa_name(best));
  const std::optional<Isa> isa = parse_isa(requested);
  if (!isa) {
    return {best, "sphray: SPHRAY_ISA=" + std::string(requested) +
                      " is not one of scalar, sse4.2, avx2, avx512, neon; using " + best_name};
  }
  if (find_entries(*isa) == nullptr) {
    return {best, "sphray: SPHRAY_ISA=" + std::string(requested) +
                      " cannot run here (not built for this CPU family, or the CPU or OS lacks "
                      "it); using " +
                      best_name};
  }
  return {*isa, {}};
}

Isa active_isa() {
  return choice().active->isa;
}

Isa bvh_isa(std::size_t sphere_count) {
  const Choice& c = choice();
  return c.tree_forced ? c.active->isa
                       : detail::tree_isa_for(c.cpu, supported_isas(), sphere_count);
}

Isa bvh_isa() {
  return bvh_isa(std::numeric_limits<std::size_t>::max());
}
namespace detail {

const EntryTable& active_entries() {
  return *choice().active;
}

const EntryTable& entries_for_size(std::size_t sphere_count) {
  const Choice& c = choice();
  return sphere_count < Choice::kSmall ? *c.by_count[sphere_count] : *c.active;
}

}  // namespace detail

}  // namespace sphray
