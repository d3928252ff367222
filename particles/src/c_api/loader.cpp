// The C functions of sphray_particles.h over sphray::particles. Every exception is caught here
// and becomes a status code and the calling thread's message: none crosses the C boundary.
#include <cstdio>
#include <memory>
#include <vector>

#include "c_api/exception_status.hpp"
#include "sphray/particles/particles.hpp"
#include "sphray/sphray_particles.h"

struct sphray_particles {
  sphray::SphereSoA spheres;
  std::vector<float> red, green, blue;  // empty when the file has no colours
};

namespace {

// Long enough for a reader's message (a quoted field is cut at 40 bytes) and a long path; a
// longer one is cut, never overflowed.
constexpr std::size_t kMessageBytes = 1024;
thread_local char message[kMessageBytes] = "";

// Sets the calling thread's message to "function: what" and returns status. Never allocates
// and never throws: it runs on the out-of-memory path too.
int fail(int status, const char* function, const char* what) noexcept {
  std::snprintf(message, kMessageBytes, "%s: %s", function, what);
  return status;
}

// Runs body(), which returns a status, and maps any exception to its status and message: a
// refused file to SPHRAY_ERROR_PARTICLE_FILE, the rest as libsphray does.
template <class Body>
int guarded(const char* function, Body&& body) noexcept {
  try {
    return body();
  } catch (const sphray::particles::ParticleError& e) {
    return fail(SPHRAY_ERROR_PARTICLE_FILE, function, e.what());
  } catch (...) {
    return sphray::c_api::status_of_exception(function, fail);
  }
}

int null_pointer(const char* function, const char* argument) noexcept {
  char what[64];
  std::snprintf(what, sizeof what, "%s is NULL", argument);
  return fail(SPHRAY_ERROR_NULL_POINTER, function, what);
}

std::unique_ptr<sphray_particles> load(const char* path, float radius) {
  sphray::particles::PointOptions options;
  if (!(radius <= 0.0f)) options.radius = radius;  // NaN too: the reader then refuses it
  sphray::particles::Points points = sphray::particles::read_particle_file(path, options);
  auto handle = std::make_unique<sphray_particles>();
  for (const sphray::Vec3& c : points.colors) {
    handle->red.push_back(c.x);
    handle->green.push_back(c.y);
    handle->blue.push_back(c.z);
  }
  handle->spheres = std::move(points.spheres);
  return handle;
}

}  // namespace

extern "C" {

int sphray_particles_load(const char* path, float radius, sphray_particles** out) {
  constexpr const char* kFunction = "sphray_particles_load";
  if (path == nullptr) return null_pointer(kFunction, "path");
  if (out == nullptr) return null_pointer(kFunction, "out");
  return guarded(kFunction, [&] {
    *out = load(path, radius).release();
    return SPHRAY_OK;
  });
}

int sphray_particles_count(const sphray_particles* particles, size_t* count) {
  constexpr const char* kFunction = "sphray_particles_count";
  if (particles == nullptr) return null_pointer(kFunction, "particles");
  if (count == nullptr) return null_pointer(kFunction, "count");
  *count = particles->spheres.size();
  return SPHRAY_OK;
}

int sphray_particles_arrays(const sphray_particles* particles, sphray_particle_arrays* out) {
  constexpr const char* kFunction = "sphray_particles_arrays";
  if (particles == nullptr) return null_pointer(kFunction, "particles");
  if (out == nullptr) return null_pointer(kFunction, "out");
  const sphray::SphereView v = particles->spheres.view();
  const bool colors = !particles->red.empty();
  *out = {v.count,
          v.cx,
          v.cy,
          v.cz,
          v.radius,
          colors ? particles->red.data() : nullptr,
          colors ? particles->green.data() : nullptr,
          colors ? particles->blue.data() : nullptr};
  return SPHRAY_OK;
}

int sphray_particles_release(sphray_particles* particles) {
  if (particles == nullptr) return null_pointer("sphray_particles_release", "particles");
  delete particles;
  return SPHRAY_OK;
}

const char* sphray_particles_last_error(void) {
  return message;
}

}  // extern "C"
