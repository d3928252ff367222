// sphray_version, sphray_version_number, sphray_active_isa, sphray_bvh_isa, sphray_last_error,
// sphray_status_name.
#include "c_api/last_error.hpp"
#include "sphray/sphray.h"
#include "sphray/sphray.hpp"

namespace {

// C strings with static storage; isa_name() returns views of the same names.
const char* c_name(sphray::Isa isa) {
  switch (isa) {
    case sphray::Isa::scalar:
      return "scalar";
    case sphray::Isa::sse4_2:
      return "sse4.2";
    case sphray::Isa::avx2:
      return "avx2";
    case sphray::Isa::avx512:
      return "avx512";
    case sphray::Isa::neon:
      return "neon";
  }
  return "unknown";
}

}  // namespace

extern "C" {

const char* sphray_version(void) {
  return sphray::kVersion;
}

int sphray_version_number(void) {
  return SPHRAY_VERSION_NUMBER;
}

const char* sphray_active_isa(void) {
  return c_name(sphray::active_isa());
}

const char* sphray_bvh_isa(size_t sphere_count) {
  return c_name(sphray::bvh_isa(sphere_count));
}

const char* sphray_last_error(void) {
  return sphray::c_api::last_error();
}

const char* sphray_status_name(int status) {
  switch (status) {
    case SPHRAY_OK:
      return "SPHRAY_OK";
    case SPHRAY_ERROR_NULL_POINTER:
      return "SPHRAY_ERROR_NULL_POINTER";
    case SPHRAY_ERROR_INVALID_ARGUMENT:
      return "SPHRAY_ERROR_INVALID_ARGUMENT";
    case SPHRAY_ERROR_TOO_LARGE:
      return "SPHRAY_ERROR_TOO_LARGE";
    case SPHRAY_ERROR_OUT_OF_MEMORY:
      return "SPHRAY_ERROR_OUT_OF_MEMORY";
    case SPHRAY_ERROR_RELEASED_SCENE:
      return "SPHRAY_ERROR_RELEASED_SCENE";
    case SPHRAY_ERROR_INTERNAL:
      return "SPHRAY_ERROR_INTERNAL";
    case SPHRAY_ERROR_PRECISION:
      return "SPHRAY_ERROR_PRECISION";
  }
  return "unknown status";
}

}  // extern "C"
