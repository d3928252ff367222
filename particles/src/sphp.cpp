// The binary particle file (.sphp): checked header, reads at offsets, the encoder.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "sphray/particles/particles.hpp"
#include "support.hpp"

namespace sphray::particles {
namespace {

constexpr std::array<char, 8> kMagic = {'S', 'P', 'H', 'R', 'A', 'Y', 'P', '\0'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kChunkRecords = 65536;  // read 1 MiB at a time

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what) {
  throw ParticleError(file.string() + ": " + what);
}

std::uint64_t load_le(const unsigned char* bytes, int n) {
  std::uint64_t v = 0;
  for (int i = n - 1; i >= 0; --i)
    v = v << 8 | bytes[i];
  return v;
}

void store_le(unsigned char* bytes, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i, v >>= 8)
    bytes[i] = static_cast<unsigned char>(v & 0xff);
}

float load_float(const unsigned char* bytes) {
  return std::bit_cast<float>(static_cast<std::uint32_t>(load_le(bytes, 4)));
}

// The rule every reader applies (the text readers field by field): a centre of at most 1e17 in
// magnitude and a radius in (0, 1e17], so that squares and the kernel's products stay finite.
bool usable(float x, float y, float z, float r) {
  constexpr float kMax = detail::kMaxMagnitude;
  return std::abs(x) <= kMax && std::abs(y) <= kMax && std::abs(z) <= kMax && r > 0.0f &&
         r <= kMax;  // NaN fails every comparison
}

[[noreturn]] void unusable(const std::filesystem::path& file, std::uint64_t i, float x, float y,
                           float z, float r) {
  using detail::shortest;
  fail(file, "particle " + std::to_string(i) + " (byte offset " +
                 std::to_string(kSphpHeaderBytes + kSphpRecordBytes * i) +
                 "): expected a centre of at most 1e17 in magnitude and a radius in (0, 1e17], "
                 "got (" +
                 shortest(x) + ", " + shortest(y) + ", " + shortest(z) + ") r " + shortest(r));
}

}  // namespace

// O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer, for ever, before
// the check that refuses it (ranks read at offsets, which only a regular file has). Reads of a
// regular file never block, so the flag changes nothing for the files that are accepted.
SphpFile::SphpFile(const std::filesystem::path& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
  if (fd_ < 0) fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  try {
    struct stat st {};
    if (::fstat(fd_, &st) != 0)
      fail(path_, std::string("cannot stat (") + std::strerror(errno) + ")");
    if (!S_ISREG(st.st_mode))
      fail(path_, S_ISFIFO(st.st_mode) ? "not a regular file (a FIFO: ranks read at offsets)"
                                       : "not a regular file");
    const auto size = static_cast<std::uint64_t>(st.st_size);
    if (size < kSphpHeaderBytes)
      fail(path, "truncated: " + std::to_string(size) + " bytes, less than the 32-byte header");
    std::array<unsigned char, kSphpHeaderBytes> header;
    read_bytes(header.data(), header.size(), 0);
    if (std::memcmp(header.data(), kMagic.data(), kMagic.size()) != 0)
      fail(path, "not a sphray particle file (no \"SPHRAYP\" magic)");
    const std::uint64_t version = load_le(&header[8], 4);
    if (version != kVersion)
      fail(path, "particle file version " + std::to_string(version) + ", expected 1");
    if (load_le(&header[12], 4) != 0 || load_le(&header[24], 8) != 0)
      fail(path, "corrupt header: reserved fields are not zero");
    const std::uint64_t count = load_le(&header[16], 8);
    if (count >= kMaxParticles)
      fail(path, "corrupt header: " + std::to_string(count) + " particles, at most 2^32 - 2");
    const std::uint64_t expected = kSphpHeaderBytes + kSphpRecordBytes * count;
    if (size != expected) {
      fail(path, std::string(size < expected ? "truncated" : "trailing bytes") +
                     ": the header says " + std::to_string(count) + " particles, " +
                     std::to_string(expected) + " bytes, the file has " + std::to_string(size));
    }
    count_ = count;
  } catch (...) {
    ::close(fd_);
    throw;
  }
}

SphpFile::~SphpFile() {
  ::close(fd_);
}

void SphpFile::read_bytes(void* out, std::size_t n, std::uint64_t offset) const {
  auto* p = static_cast<unsigned char*>(out);
  while (n > 0) {
    const ssize_t got = ::pread(fd_, p, n, static_cast<off_t>(offset));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) fail(path_, std::string("read error (") + std::strerror(errno) + ")");
    if (got == 0) fail(path_, "truncated while reading (the file shrank?)");
    p += got;
    n -= static_cast<std::size_t>(got);
    offset += static_cast<std::uint64_t>(got);
  }
}

void SphpFile::read(std::uint64_t first, std::uint64_t end, SphereSoA& spheres,
                    std::vector<std::uint32_t>* ids) const {
  spheres.reserve(spheres.size() + (end - first));
  if (ids != nullptr) ids->reserve(ids->size() + (end - first));
  std::vector<unsigned char> chunk(kChunkRecords * kSphpRecordBytes);
  for (std::uint64_t i = first; i < end;) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kChunkRecords, end - i));
    read_bytes(chunk.data(), n * kSphpRecordBytes, kSphpHeaderBytes + i * kSphpRecordBytes);
    for (std::size_t k = 0; k < n; ++k, ++i) {
      const unsigned char* record = &chunk[k * kSphpRecordBytes];
      const float x = load_float(record), y = load_float(record + 4), z = load_float(record + 8),
                  r = load_float(record + 12);
      if (!usable(x, y, z, r)) unusable(path_, i, x, y, z, r);
      spheres.add({x, y, z}, r);
      if (ids != nullptr) ids->push_back(static_cast<std::uint32_t>(i));
    }
  }
}

bool SphpFile::named(const std::filesystem::path& path) {
  return detail::lower(path.extension().string()) == ".sphp";
}

SphereSoA read_sphp(const std::filesystem::path& path) {
  const SphpFile file(path);
  SphereSoA spheres;
  file.read(0, file.count(), spheres);
  return spheres;
}

void check_particle_count(std::uint64_t count) {
  if (count >= kMaxParticles)
    throw ParticleError("too many particles for one file: at most 2^32 - 2");
}

void write_sphp(const ByteSink& sink, SphereView spheres, std::span<const std::uint32_t> order) {
  check_particle_count(spheres.count);
  std::array<unsigned char, kSphpHeaderBytes> header{};
  std::memcpy(header.data(), kMagic.data(), kMagic.size());
  store_le(&header[8], kVersion, 4);
  store_le(&header[16], spheres.count, 8);
  sink(header.data(), header.size());
  std::vector<unsigned char> chunk;
  chunk.reserve(kChunkRecords * kSphpRecordBytes);
  for (std::size_t k = 0; k < spheres.count; ++k) {
    const std::size_t i = order.empty() ? k : order[k];
    for (float v : {spheres.cx[i], spheres.cy[i], spheres.cz[i], spheres.radius[i]}) {
      unsigned char bytes[4];
      store_le(bytes, std::bit_cast<std::uint32_t>(v), 4);
      chunk.insert(chunk.end(), bytes, bytes + 4);
    }
    if (chunk.size() == chunk.capacity() || k + 1 == spheres.count) {
      sink(chunk.data(), chunk.size());
      chunk.clear();
    }
  }
}

}  // namespace sphray::particles
