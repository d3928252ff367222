#include "c_api/scene_handle.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <mutex>
#include <new>
#include <utility>
#include <vector>

namespace sphray::c_api {
namespace {

// Address space reserved for handles at a time: 4 Mi handles. Only the pages handles occupy
// are ever backed by memory (an anonymous mapping is backed on first touch).
constexpr std::size_t kChunkBytes = std::size_t{64} << 20;

// A reservation, handed out front to back, never reused: a released handle's address is never
// a live handle again. live[p] counts the live handles of its page p.
struct Chunk {
  std::byte* base = nullptr;
  std::size_t used = 0;
  std::vector<std::uint32_t> live;
};

// Only create and release take the lock, never a query. The chunks stay mapped for as long as
// the library is loaded.
std::mutex handle_mutex;
std::vector<Chunk> chunks;

std::size_t page_bytes() {
  static const auto bytes = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  return bytes;
}

Chunk& chunk_with_room() {
  static_assert(sizeof(sphray_scene) == 16);  // a power of two: no handle straddles a page
  if (chunks.empty() || chunks.back().used + sizeof(sphray_scene) > kChunkBytes) {
    // What can throw comes first, so that a throw leaves nothing mapped.
    std::vector<std::uint32_t> live(kChunkBytes / page_bytes(), 0);
    chunks.reserve(chunks.size() + 1);
    void* base = mmap(nullptr, kChunkBytes, PROT_READ | PROT_WRITE,
                      MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (base == MAP_FAILED) throw std::bad_alloc();
    chunks.push_back({static_cast<std::byte*>(base), 0, std::move(live)});
  }
  return chunks.back();
}

// A fresh handle's memory, zeroed (never used before).
sphray_scene* new_handle() {
  std::lock_guard lock(handle_mutex);
  Chunk& chunk = chunk_with_room();
  std::byte* at = chunk.base + chunk.used;
  chunk.used += sizeof(sphray_scene);
  ++chunk.live[static_cast<std::size_t>(at - chunk.base) / page_bytes()];
  return new (at) sphray_scene;
}

// One live handle fewer on its page; a page whose handles are all handed out and all released
// goes back to the system, to read as zeros from then on (Linux's MADV_DONTNEED on a private
// anonymous mapping). Elsewhere the page stays, its handles marked released.
void drop_handle(sphray_scene* handle) {
  std::lock_guard lock(handle_mutex);
  const auto* at = reinterpret_cast<const std::byte*>(handle);
  const auto owner = std::find_if(chunks.begin(), chunks.end(), [&](const Chunk& c) {
    return at >= c.base && at < c.base + kChunkBytes;
  });
  if (owner == chunks.end()) return;
  const std::size_t page = static_cast<std::size_t>(at - owner->base) / page_bytes();
  const bool handed_out = owner->used >= (page + 1) * page_bytes();
  if (--owner->live[page] != 0 || !handed_out) return;
#if defined(__linux__)
  madvise(owner->base + page * page_bytes(), page_bytes(), MADV_DONTNEED);
#endif
}

}  // namespace

sphray_scene* adopt(Scene* scene) {
  sphray_scene* handle = nullptr;
  try {
    handle = new_handle();
  } catch (...) {
    delete scene;
    throw;
  }
  handle->scene = scene;
  handle->magic = sphray_scene::kLive;
  return handle;
}

void retire(sphray_scene* handle) noexcept {
  delete handle->scene;
  handle->scene = nullptr;
  handle->magic = sphray_scene::kReleased;
  drop_handle(handle);
}

}  // namespace sphray::c_api
