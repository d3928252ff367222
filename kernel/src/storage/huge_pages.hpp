// Large arrays on huge pages where the system allows it.
//
// A 100-million-sphere scene fills its arrays (1.6 GB of spheres, as much again for the build's
// records and the tree) page by page; with 4 KiB pages that is one page fault per 4 KiB, and the
// faults, not the copying, bound reading a particle file and building the tree. Linux's
// transparent huge pages, in their usual "madvise" setting, give 2 MiB pages only to the ranges a
// program asks for: this asks for them on a fresh allocation, before its first touch. The data and
// every result are the same either way; elsewhere it does nothing.
#pragma once

#include <cstddef>
#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace sphray::detail {

inline void prefer_huge_pages(void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  if (bytes < 2 * kHuge) return;  // too small for a whole huge page inside
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t last = (begin + bytes) & ~(kHuge - 1);
  // Advice only: a refusal (no THP, a kernel without it) leaves ordinary pages.
  if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

}  // namespace sphray::detail
