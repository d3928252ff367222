// Text points fuzzer: any bytes given to parse_points() give either particles the kernel can
// use (finite centres, radii in (0, 1e17], colours in [0, 1], one per particle or none) or a
// ParticleError whose message is one line naming the source. Anything else (another exception,
// a crash, undefined behaviour, a leak, a hang) is a finding.
//
// The first byte chooses the radius given for the file: '@' none, anything else 0.5; the rest is
// the file.
#include <cstdint>
#include <string>
#include <string_view>

#include "particle_checks.hpp"
#include "sphray/particles/particles.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  sphray::particles::PointOptions options;
  if (data[0] != '@') options.radius = 0.5f;
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  const std::string source = "fuzz.xyz";
  try {
    sphray::fuzz::check_points("points", sphray::particles::parse_points(text, source, options));
  } catch (const sphray::particles::ParticleError& e) {
    sphray::fuzz::check_refusal("points", e, source);
  }
  return 0;
}
