// The C API's error reporting: a status code returned, and a message kept per thread for
// sphray_last_error(). No exception leaves the library through a C function: guarded() turns
// every one into its status code.
#pragma once

#include <exception>
#include <new>
#include <stdexcept>

#include "sphray/sphray.h"

namespace sphray::c_api {

/// Sets the calling thread's message to "function: what" and returns status. Never allocates
/// (a fixed per-thread buffer, the message truncated to fit) and never throws: it runs on the
/// out-of-memory path too.
int fail(int status, const char* function, const char* what) noexcept;

/// The calling thread's message ("" before the first failure).
const char* last_error() noexcept;

/// Runs body(), which returns a status, and maps any exception to its status and message: an
/// allocation failure to SPHRAY_ERROR_OUT_OF_MEMORY, std::length_error (the library's "too
/// many" error) to SPHRAY_ERROR_TOO_LARGE, std::invalid_argument to
/// SPHRAY_ERROR_INVALID_ARGUMENT, anything else to SPHRAY_ERROR_INTERNAL.
template <class Body>
int guarded(const char* function, Body&& body) noexcept {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    return fail(SPHRAY_ERROR_OUT_OF_MEMORY, function, "out of memory");
  } catch (const std::length_error& e) {
    return fail(SPHRAY_ERROR_TOO_LARGE, function, e.what());
  } catch (const std::invalid_argument& e) {
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function, e.what());
  } catch (const std::exception& e) {
    return fail(SPHRAY_ERROR_INTERNAL, function, e.what());
  } catch (...) {
    return fail(SPHRAY_ERROR_INTERNAL, function, "unknown exception");
  }
}

}  // namespace sphray::c_api
