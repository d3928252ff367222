// PDB fuzzer: any bytes given to parse_pdb() give either atoms the kernel can use (the checks of
// particle_checks.hpp, with one colour per atom and a radius from the element table) or a
// ParticleError whose message is one line naming the source. Anything else (another exception,
// a crash, undefined behaviour, a leak, a hang) is a finding.
#include <cstdint>
#include <string>
#include <string_view>

#include "particle_checks.hpp"
#include "sphray/particles/particles.hpp"

namespace {

constexpr const char* kFuzzer = "pdb";

void check_atoms(const sphray::particles::Points& points) {
  sphray::fuzz::check_points(kFuzzer, points);
  const sphray::SphereView v = points.spheres.view();
  if (points.colors.size() != v.count)
    sphray::fuzz::fail(kFuzzer, "not one colour per atom", std::to_string(points.colors.size()));
  for (std::size_t i = 0; i < v.count; ++i) {
    // Every radius of the table is between hydrogen's 1.20 and francium's 3.48 angstroms.
    if (!(v.radius[i] >= 1.2f && v.radius[i] <= 3.48f))
      sphray::fuzz::fail(kFuzzer, "a radius outside the element table",
                         std::to_string(v.radius[i]));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string source = "fuzz.pdb";
  try {
    check_atoms(sphray::particles::parse_pdb(text, source));
  } catch (const sphray::particles::ParticleError& e) {
    sphray::fuzz::check_refusal(kFuzzer, e, source);
  }
  return 0;
}
