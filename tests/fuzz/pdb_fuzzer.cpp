// PDB fuzzer: any bytes given to parse_pdb() give either atoms the kernel can use (finite
// centres within 1e17, radii of the element table, one colour per atom in [0, 1]) or a
// ParticleError whose message is one line naming the source. Anything else (another exception,
// a crash, undefined behaviour, a leak, a hang) is a finding.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "sphray/particles/particles.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "pdb fuzzer: %s: %s\n", what, detail.c_str());
  std::abort();
}

void check_atoms(const sphray::particles::Points& points) {
  const sphray::SphereView v = points.spheres.view();
  if (v.count == 0) fail("accepted a file without atoms", "");
  if (points.colors.size() != v.count)
    fail("not one colour per atom", std::to_string(points.colors.size()));
  for (std::size_t i = 0; i < v.count; ++i) {
    for (float c : {v.cx[i], v.cy[i], v.cz[i]}) {
      if (!std::isfinite(c) || std::abs(c) > 1e17f) fail("accepted a centre out of range", "");
    }
    // Every radius of the table is between hydrogen's 1.20 and francium's 3.48 angstroms.
    if (!(v.radius[i] >= 1.2f && v.radius[i] <= 3.48f))
      fail("a radius outside the element table", std::to_string(v.radius[i]));
  }
  for (const sphray::Vec3& c : points.colors) {
    for (float k : {c.x, c.y, c.z}) {
      if (!(k >= 0.0f && k <= 1.0f)) fail("a colour outside [0, 1]", "");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string source = "fuzz.pdb";
  try {
    check_atoms(sphray::particles::parse_pdb(text, source));
  } catch (const sphray::particles::ParticleError& e) {
    const std::string message = e.what();
    if (!message.starts_with(source + ":")) fail("a message that does not name the file", message);
    if (message.find('\n') != std::string::npos || message.find('\r') != std::string::npos)
      fail("a message of more than one line", message);
  }
  return 0;
}
