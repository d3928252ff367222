// Text points fuzzer: any bytes given to parse_points() give either particles the kernel can
// use (finite centres, radii in (0, 1e17], colours in [0, 1], one per particle or none) or a
// ParticleError whose message is one line naming the source. Anything else (another exception,
// a crash, undefined behaviour, a leak, a hang) is a finding.
//
// The first byte chooses the radius given for the file: '@' none, anything else 0.5; the rest is
// the file.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "sphray/particles/particles.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "points fuzzer: %s: %s\n", what, detail.c_str());
  std::abort();
}

void check_points(const sphray::particles::Points& points) {
  const sphray::SphereView v = points.spheres.view();
  if (v.count == 0) fail("accepted a file without particles", "");
  if (!points.colors.empty() && points.colors.size() != v.count)
    fail("colours and particles differ in number", std::to_string(points.colors.size()));
  for (std::size_t i = 0; i < v.count; ++i) {
    for (float c : {v.cx[i], v.cy[i], v.cz[i]}) {
      if (!std::isfinite(c) || std::abs(c) > 1e17f) fail("accepted a centre out of range", "");
    }
    if (!(v.radius[i] > 0.0f && v.radius[i] <= 1e17f)) fail("accepted a bad radius", "");
  }
  for (const sphray::Vec3& c : points.colors) {
    for (float k : {c.x, c.y, c.z}) {
      if (!(k >= 0.0f && k <= 1.0f)) fail("accepted a colour outside [0, 1]", "");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  sphray::particles::PointOptions options;
  if (data[0] != '@') options.radius = 0.5f;
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  const std::string source = "fuzz.xyz";
  try {
    check_points(sphray::particles::parse_points(text, source, options));
  } catch (const sphray::particles::ParticleError& e) {
    const std::string message = e.what();
    if (!message.starts_with(source + ":")) fail("a message that does not name the file", message);
    if (message.find('\n') != std::string::npos || message.find('\r') != std::string::npos)
      fail("a message of more than one line", message);
  }
  return 0;
}
