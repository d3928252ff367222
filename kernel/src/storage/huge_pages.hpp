// Large arrays on huge pages where the system allows it, and given back page by page once read.
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
#include <unistd.h>
#endif

namespace sphray::detail {

#if defined(__linux__)
// madvise(advice) on the whole pages of page_size bytes (a power of two) inside
// [data, data + bytes); nothing when none fits. Advice only: a refusal changes nothing.
inline void advise_whole_pages(const void* data, std::size_t bytes, std::uintptr_t page_size,
                               int advice) {
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + page_size - 1) & ~(page_size - 1);
  const std::uintptr_t last = (begin + bytes) & ~(page_size - 1);
  if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, advice);
}
#endif

inline void prefer_huge_pages(void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  // A refusal (no THP, a kernel without it) leaves ordinary pages.
  if (bytes >= 2 * kHuge) advise_whole_pages(data, bytes, kHuge, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

// Gives the whole pages inside [data, data + bytes) back to the system while the array lives on:
// for an array read once from front to back that would otherwise hold its memory until its last
// element is read (the tree build's records while the tree's slots are written, issue 34). The
// pages' contents are lost; the caller never reads them again. Elsewhere it does nothing.
inline void release_pages(const void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_DONTNEED)
  advise_whole_pages(data, bytes, static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE)),
                     MADV_DONTNEED);
#else
  (void)data;
  (void)bytes;
#endif
}

}  // namespace sphray::detail
