#include "sphray/render/memory_check.hpp"

#include <sys/mman.h>
#include <sys/resource.h>

#include <cstdio>

namespace sphray::render {

bool can_map(std::size_t bytes) {
  if (bytes == 0) return true;
  // No MAP_NORESERVE: the mapping is then charged like a malloc of that size would be.
  void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) return false;
  ::munmap(p, bytes);
  return true;
}

std::string format_bytes(std::size_t bytes) {
  constexpr double kMiB = 1024.0 * 1024.0;
  char text[32];
  const double mib = static_cast<double>(bytes) / kMiB;
  if (mib >= 1024.0) {
    std::snprintf(text, sizeof text, "%.1f GiB", mib / 1024.0);
  } else {
    std::snprintf(text, sizeof text, "%.0f MiB", mib < 1.0 ? 1.0 : mib);
  }
  return text;
}

void require_memory(std::size_t bytes, const std::string& what) {
  if (can_map(bytes)) return;
  std::string why = "the system's memory";
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
    why = "ulimit -v is " + format_bytes(static_cast<std::size_t>(limit.rlim_cur));
  throw InsufficientMemory(what + " needs about " + format_bytes(bytes) +
                           " of memory, which this process cannot get (" + why + ")");
}

}  // namespace sphray::render
