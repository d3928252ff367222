// The C API's error reporting: a status code returned, and a message kept per thread for
// sphray_last_error(). No exception leaves the library through a C function: guarded() turns
// every one into its status code.
#pragma once

#include "c_api/exception_status.hpp"
#include "sphray/sphray.h"

namespace sphray::c_api {

/// Sets the calling thread's message to "function: what" and returns status. Never allocates
/// (a fixed per-thread buffer, the message truncated to fit) and never throws: it runs on the
/// out-of-memory path too.
int fail(int status, const char* function, const char* what) noexcept;

/// The calling thread's message ("" before the first failure).
const char* last_error() noexcept;

/// Runs body(), which returns a status, and maps any exception to its status and message
/// (status_of_exception).
template <class Body>
int guarded(const char* function, Body&& body) noexcept {
  try {
    return body();
  } catch (...) {
    return status_of_exception(function, fail);
  }
}

}  // namespace sphray::c_api
