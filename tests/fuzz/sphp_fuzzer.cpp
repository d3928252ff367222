// .sphp fuzzer: any bytes as a binary particle file give either particles the kernel can use
// (particle_checks.hpp) that write_sphp() writes back as the same bytes, or a ParticleError whose
// message is one line naming the file. Anything else (another exception, a crash, undefined
// behaviour, a leak, a hang, memory out of proportion to the input) is a finding.
//
// The reader takes a path and reads with pread, so the bytes go to an anonymous in-memory file
// (memfd_create: a regular file, as the reader requires) named through /proc/self/fd.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <string>

#include "particle_checks.hpp"
#include "sphray/particles/particles.hpp"

namespace {

std::string written_again(const sphray::SphereSoA& spheres) {
  std::string bytes;
  sphray::particles::write_sphp(
      [&](const void* data, std::size_t size) {
        bytes.append(static_cast<const char*>(data), size);
      },
      spheres.view());
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const int fd = ::memfd_create("fuzz.sphp", MFD_CLOEXEC);
  if (fd < 0) sphray::fuzz::fail("sphp", "memfd_create failed", "");
  if (size > 0 && ::write(fd, data, size) != static_cast<ssize_t>(size))
    sphray::fuzz::fail("sphp", "writing the memfd failed", "");
  const std::string path = "/proc/self/fd/" + std::to_string(fd);
  try {
    sphray::particles::Points points;
    points.spheres = sphray::particles::read_sphp(path);
    if (points.spheres.size() > 0) sphray::fuzz::check_points("sphp", points);
    if (written_again(points.spheres) != std::string(reinterpret_cast<const char*>(data), size))
      sphray::fuzz::fail("sphp", "write_sphp wrote other bytes than were read", "");
  } catch (const sphray::particles::ParticleError& e) {
    sphray::fuzz::check_refusal("sphp", e, path);
  }
  ::close(fd);
  return 0;
}
