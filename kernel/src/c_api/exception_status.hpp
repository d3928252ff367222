// How every C function of sphray's libraries turns the exception being handled into a status
// code and a message, so that libsphray and libsphray_particles answer the same exception the
// same way. Header-only: each library keeps its own per-thread message (its own fail()).
#pragma once

#include <exception>
#include <new>
#include <stdexcept>

#include "sphray/sphray.h"

namespace sphray::c_api {

/// Called in a catch handler: the status of the exception being handled, its message given to
/// fail(status, function, what), which returns the status: an allocation failure is
/// SPHRAY_ERROR_OUT_OF_MEMORY, std::length_error (the library's "too many" error)
/// SPHRAY_ERROR_TOO_LARGE, std::invalid_argument SPHRAY_ERROR_INVALID_ARGUMENT, anything else
/// SPHRAY_ERROR_INTERNAL. A library with exceptions of its own catches them before calling this.
template <class Fail>
int status_of_exception(const char* function, Fail&& fail) noexcept {
  try {
    throw;
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
