#include "sphray/mpi/particle_file.hpp"

#include <algorithm>
#include <array>
#include <new>

#include "sphray/mpi/agreement.hpp"
#include "sphray/mpi/spatial_split.hpp"

namespace sphray::mpi {
namespace {

using particles::kSphpHeaderBytes;
using particles::kSphpRecordBytes;
using particles::SphpFile;

// Records every rank reads besides its own run, spread evenly over the file, and hashes with
// the header: the ranks compare the hashes to find copies of the file that differ.
constexpr std::uint64_t kSampleRecords = 256;

// A hash of the header and of kSampleRecords records spread over the file, the same on every
// rank that reads the same bytes. It cannot see every change (that would need every rank to read
// the whole file), but it sees a file replaced by another or a copy that differs throughout.
std::uint64_t sample_hash(const SphpFile& in) {
  const std::uint64_t total = in.count();
  Fnv1a hash;
  std::array<unsigned char, kSphpHeaderBytes> header;
  in.read_bytes(header.data(), header.size(), 0);
  hash.add(header.data(), header.size());
  const std::uint64_t samples = std::min(total, kSampleRecords);
  for (std::uint64_t k = 0; k < samples; ++k) {
    std::array<unsigned char, kSphpRecordBytes> record;
    in.read_bytes(record.data(), record.size(),
                  kSphpHeaderBytes + (total * k / samples) * kSphpRecordBytes);
    hash.add(record.data(), record.size());
  }
  return hash.value();
}

ParticleShare read_run(const std::filesystem::path& path, int rank, int ranks,
                       std::uint64_t& hash) {
  const SphpFile in(path);
  ParticleShare share;
  share.total = in.count();
  hash = sample_hash(in);
  const std::uint64_t first =
      share.total * static_cast<std::uint64_t>(rank) / static_cast<std::uint64_t>(ranks);
  const std::uint64_t end =
      share.total * static_cast<std::uint64_t>(rank + 1) / static_cast<std::uint64_t>(ranks);
  in.read(first, end, share.spheres, &share.ids);
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
  particles::check_particle_count(spheres.count);  // before the order is computed
  const std::vector<std::uint32_t> order = morton_order(spheres);
  particles::write_sphp(sink, spheres, order);
}

}  // namespace sphray::mpi
