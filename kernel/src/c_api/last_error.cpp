#include "c_api/last_error.hpp"

#include <cstdio>

namespace sphray::c_api {
namespace {

// Long enough for any message the library writes; a longer one is cut, never overflowed.
constexpr std::size_t kMessageBytes = 512;
thread_local char message[kMessageBytes] = "";

}  // namespace

int fail(int status, const char* function, const char* what) noexcept {
  std::snprintf(message, kMessageBytes, "%s: %s", function, what);
  return status;
}

const char* last_error() noexcept {
  return message;
}

}  // namespace sphray::c_api
