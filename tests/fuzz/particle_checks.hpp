// What the particle fuzzers check of the particles a reader accepts: what the kernel can use
// (finite centres, radii in (0, 1e17], colours in [0, 1], one per particle or none), and a
// refusal that is one line naming the source.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "sphray/particles/particles.hpp"

namespace sphray::fuzz {

[[noreturn]] inline void fail(const char* fuzzer, const char* what, const std::string& detail) {
  std::fprintf(stderr, "%s fuzzer: %s: %s\n", fuzzer, what, detail.c_str());
  std::abort();
}

inline void check_points(const char* fuzzer, const particles::Points& points) {
  const SphereView v = points.spheres.view();
  if (v.count == 0) fail(fuzzer, "accepted a file without particles", "");
  if (!points.colors.empty() && points.colors.size() != v.count)
    fail(fuzzer, "colours and particles differ in number", std::to_string(points.colors.size()));
  for (std::size_t i = 0; i < v.count; ++i) {
    for (float c : {v.cx[i], v.cy[i], v.cz[i]}) {
      if (!std::isfinite(c) || std::abs(c) > 1e17f)
        fail(fuzzer, "accepted a centre out of range", "");
    }
    if (!(v.radius[i] > 0.0f && v.radius[i] <= 1e17f)) fail(fuzzer, "accepted a bad radius", "");
  }
  for (const Vec3& c : points.colors) {
    for (float k : {c.x, c.y, c.z}) {
      if (!(k >= 0.0f && k <= 1.0f)) fail(fuzzer, "accepted a colour outside [0, 1]", "");
    }
  }
}

inline void check_refusal(const char* fuzzer, const particles::ParticleError& e,
                          const std::string& source) {
  const std::string message = e.what();
  if (!message.starts_with(source + ":"))
    fail(fuzzer, "a message that does not name the file", message);
  if (message.find('\n') != std::string::npos || message.find('\r') != std::string::npos)
    fail(fuzzer, "a message of more than one line", message);
}

}  // namespace sphray::fuzz
