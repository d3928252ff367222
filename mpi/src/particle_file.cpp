#include "sphray/mpi/particle_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstring>
#include <new>

#include "sphray/mpi/agreement.hpp"
#include "sphray/mpi/spatial_split.hpp"

namespace sphray::mpi {
namespace {

constexpr std::array<char, 8> kMagic = {'S', 'P', 'H', 'R', 'A', 'Y', 'P', '\0'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 32;
constexpr std::size_t kRecordBytes = 16;
constexpr std::size_t kChunkRecords = 65536;     // read 1 MiB at a time
constexpr std::uint64_t kMaxParticles = kNoHit;  // ids 0 to 2^32 - 2: kNoHit is no id
// Records every rank reads besides its own run, spread evenly over the file, and hashes with
// the header: the ranks compare the hashes to find copies of the file that differ.
constexpr std::uint64_t kSampleRecords = 256;

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
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer, for ever, before
  // the check that refuses it (ranks read at offsets, which only a regular file has). Reads of a
  // regular file never block, so the flag changes nothing for the files that are accepted.
  explicit File(const std::filesystem::path& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    if (fd_ < 0) fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  }
  ~File() { ::close(fd_); }
  File(const File&) = delete;
  File& operator=(const File&) = delete;

  std::uint64_t size() const {
    struct stat st {};
    if (::fstat(fd_, &st) != 0)
      fail(path_, std::string("cannot stat (") + std::strerror(errno) + ")");
    if (!S_ISREG(st.st_mode))
      fail(path_, S_ISFIFO(st.st_mode) ? "not a regular file (a FIFO: ranks read at offsets)"
                                       : "not a regular file");
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

// A hash of the header and of kSampleRecords records spread over the file, the same on every
// rank that reads the same bytes. It cannot see every change (that would need every rank to read
// the whole file), but it sees a file replaced by another or a copy that differs throughout.
std::uint64_t sample_hash(const File& in, std::uint64_t total) {
  Fnv1a hash;
  std::array<unsigned char, kHeaderBytes> header;
  in.read(header.data(), header.size(), 0);
  hash.add(header.data(), header.size());
  const std::uint64_t samples = std::min(total, kSampleRecords);
  for (std::uint64_t k = 0; k < samples; ++k) {
    std::array<unsigned char, kRecordBytes> record;
    in.read(record.data(), record.size(), kHeaderBytes + (total * k / samples) * kRecordBytes);
    hash.add(record.data(), record.size());
  }
  return hash.value();
}

ParticleShare read_run(const std::filesystem::path& path, int rank, int ranks,
                       std::uint64_t& hash) {
  const File in(path);
  ParticleShare share;
  share.total = checked_count(in, path);
  hash = sample_hash(in, share.total);
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
  std::uint64_t hash = 0;
  RankError mine;
  try {
    share = read_run(file, rank, ranks, hash);
  } catch (const ParticleFileError& e) {
    mine = {1, e.what()};
  } catch (const std::bad_alloc&) {
    mine = {1, file.string() + ": out of memory reading rank " + std::to_string(rank) + "'s part"};
  }
  // Every rank learns whether any failed, and why, so that all stop together.
  const RankError first = first_error(comm, mine);
  if (first.status != 0) throw ParticleFileError(first.message);
  // Ranks that read different files (a node-local copy that differs, a file replaced while the
  // job starts) would read runs that overlap or leave gaps, and trace different spheres.
  const Setting settings[] = {{"the particle count", share.total},
                              {"the hash of the header and sampled records", hash, false}};
  const std::vector<Disagreement> differing = disagreements(comm, settings);
  if (!differing.empty()) {
    throw ParticleFileError(file.string() + ": the ranks read different files (they differ in " +
                            describe(differing) + ")");
  }
  return share;
}

void write_particles(const ByteSink& sink, SphereView spheres) {
  if (spheres.count >= kMaxParticles)
    throw ParticleFileError("too many particles for one file: at most 2^32 - 2");
  std::array<unsigned char, kHeaderBytes> header{};
  std::memcpy(header.data(), kMagic.data(), kMagic.size());
  store_le(&header[8], kVersion, 4);
  store_le(&header[16], spheres.count, 8);
  sink(header.data(), header.size());
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
      sink(chunk.data(), chunk.size());
      chunk.clear();
    }
  }
}

}  // namespace sphray::mpi
