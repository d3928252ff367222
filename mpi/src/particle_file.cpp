#include "sphray/mpi/particle_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <new>

#include "sphray/mpi/spatial_split.hpp"

namespace sphray::mpi {
namespace {

constexpr std::array<char, 8> kMagic = {'S', 'P', 'H', 'R', 'A', 'Y', 'P', '\0'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 32;
constexpr std::size_t kRecordBytes = 16;
constexpr std::size_t kChunkRecords = 65536;     // read 1 MiB at a time
constexpr std::uint64_t kMaxParticles = kNoHit;  // ids 0 to 2^32 - 2: kNoHit is no id

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what) {
  throw ParticleFileError(file.string() + ": " + what);
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

class File {
 public:
  explicit File(const std::filesystem::path& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  }
  ~File() { ::close(fd_); }
  File(const File&) = delete;
  File& operator=(const File&) = delete;

  std::uint64_t size() const {
    struct stat st {};
    if (::fstat(fd_, &st) != 0)
      fail(path_, std::string("cannot stat (") + std::strerror(errno) + ")");
    if (!S_ISREG(st.st_mode)) fail(path_, "not a regular file");
    return static_cast<std::uint64_t>(st.st_size);
  }

  // Exactly n bytes at offset, or a ParticleFileError.
  void read(void* out, std::size_t n, std::uint64_t offset) const {
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

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

// The header's particle count, after checking the header and the file's size against it.
std::uint64_t checked_count(const File& in, const std::filesystem::path& path) {
  const std::uint64_t size = in.size();
  if (size < kHeaderBytes)
    fail(path, "truncated: " + std::to_string(size) + " bytes, less than the 32-byte header");
  std::array<unsigned char, kHeaderBytes> header;
  in.read(header.data(), header.size(), 0);
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
  const std::uint64_t expected = kHeaderBytes + kRecordBytes * count;
  if (size != expected) {
    fail(path, std::string(size < expected ? "truncated" : "trailing bytes") +
                   ": the header says " + std::to_string(count) + " particles, " +
                   std::to_string(expected) + " bytes, the file has " + std::to_string(size));
  }
  return count;
}

ParticleShare read_run(const std::filesystem::path& path, int rank, int ranks) {
  const File in(path);
  ParticleShare share;
  share.total = checked_count(in, path);
  const std::uint64_t first =
      share.total * static_cast<std::uint64_t>(rank) / static_cast<std::uint64_t>(ranks);
  const std::uint64_t end =
      share.total * static_cast<std::uint64_t>(rank + 1) / static_cast<std::uint64_t>(ranks);
  share.spheres.reserve(end - first);
  share.ids.reserve(end - first);
  std::vector<unsigned char> chunk(kChunkRecords * kRecordBytes);
  for (std::uint64_t i = first; i < end;) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kChunkRecords, end - i));
    in.read(chunk.data(), n * kRecordBytes, kHeaderBytes + i * kRecordBytes);
    for (std::size_t k = 0; k < n; ++k, ++i) {
      const unsigned char* record = &chunk[k * kRecordBytes];
      share.spheres.add({load_float(record), load_float(record + 4), load_float(record + 8)},
                        load_float(record + 12));
      share.ids.push_back(static_cast<std::uint32_t>(i));
    }
  }
  return share;
}

}  // namespace

ParticleShare read_particle_share(MPI_Comm comm, const std::filesystem::path& file) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  ParticleShare share;
  std::string error;
  try {
    share = read_run(file, rank, ranks);
  } catch (const ParticleFileError& e) {
    error = e.what();
  } catch (const std::bad_alloc&) {
    error = file.string() + ": out of memory reading rank " + std::to_string(rank) + "'s part";
  }
  // Every rank learns whether any failed, so that all stop together.
  int failed = error.empty() ? 0 : 1, any = 0;
  MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, comm);
  if (any != 0) {
    if (error.empty()) error = file.string() + ": another rank could not read its part";
    throw ParticleFileError(error);
  }
  return share;
}

void write_particles(const std::filesystem::path& file, SphereView spheres) {
  if (spheres.count >= kMaxParticles) fail(file, "too many particles for one file");
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) fail(file, std::string("cannot create (") + std::strerror(errno) + ")");
  std::array<unsigned char, kHeaderBytes> header{};
  std::memcpy(header.data(), kMagic.data(), kMagic.size());
  store_le(&header[8], kVersion, 4);
  store_le(&header[16], spheres.count, 8);
  out.write(reinterpret_cast<const char*>(header.data()), header.size());
  std::vector<unsigned char> chunk;
  chunk.reserve(kChunkRecords * kRecordBytes);
  const std::vector<std::uint32_t> order = morton_order(spheres);
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::uint32_t i = order[k];
    for (float v : {spheres.cx[i], spheres.cy[i], spheres.cz[i], spheres.radius[i]}) {
      unsigned char bytes[4];
      store_le(bytes, std::bit_cast<std::uint32_t>(v), 4);
      chunk.insert(chunk.end(), bytes, bytes + 4);
    }
    if (chunk.size() == chunk.capacity() || k + 1 == order.size()) {
      out.write(reinterpret_cast<const char*>(chunk.data()),
                static_cast<std::streamsize>(chunk.size()));
      chunk.clear();
    }
  }
  out.close();
  if (!out) fail(file, "write error");
}

}  // namespace sphray::mpi
