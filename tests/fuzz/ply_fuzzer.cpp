// PLY fuzzer: any bytes given to parse_ply() give either particles the kernel can use or a
// ParticleError whose message is one line naming the source (particle_checks.hpp); particles
// that are accepted, written again by write_ply(), read back as the same bits. Anything else
// (another exception, a crash, undefined behaviour, a leak, a hang, memory out of proportion to
// the input) is a finding.
//
// The first byte chooses the radius given for the file: '@' none, anything else 0.5; the rest is
// the file.
#include <bit>
#include <cstdint>
#include <string>
#include <string_view>

#include "particle_checks.hpp"
#include "sphray/particles/particles.hpp"

namespace {

// write_ply() then parse_ply(): the same spheres, bit for bit, and as many colours.
void check_round_trip(const sphray::particles::Points& points) {
  std::string bytes;
  sphray::particles::write_ply(
      [&](const void* data, std::size_t size) {
        bytes.append(static_cast<const char*>(data), size);
      },
      points.spheres.view(), points.colors);
  const sphray::particles::Points again = sphray::particles::parse_ply(bytes, "again.ply");
  const sphray::SphereView a = points.spheres.view(), b = again.spheres.view();
  if (a.count != b.count || points.colors.size() != again.colors.size())
    sphray::fuzz::fail("ply", "write_ply read back a different count", std::to_string(b.count));
  for (std::size_t i = 0; i < a.count; ++i) {
    for (auto [x, y] : {std::pair{a.cx[i], b.cx[i]}, std::pair{a.cy[i], b.cy[i]},
                        std::pair{a.cz[i], b.cz[i]}, std::pair{a.radius[i], b.radius[i]}}) {
      if (std::bit_cast<std::uint32_t>(x) != std::bit_cast<std::uint32_t>(y))
        sphray::fuzz::fail("ply", "write_ply read back different bits", std::to_string(i));
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  sphray::particles::PointOptions options;
  if (data[0] != '@') options.radius = 0.5f;
  const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  const std::string source = "fuzz.ply";
  sphray::particles::Points points;
  try {
    points = sphray::particles::parse_ply(bytes, source, options);
  } catch (const sphray::particles::ParticleError& e) {
    sphray::fuzz::check_refusal("ply", e, source);
    return 0;
  }
  sphray::fuzz::check_points("ply", points);
  check_round_trip(points);
  return 0;
}
