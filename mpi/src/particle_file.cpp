#include "sphray/mpi/particle_file.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <new>
#include <string>

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

// Particles [total * rank / ranks, total * (rank + 1) / ranks): every rank's run.
std::uint64_t run_start(std::uint64_t total, int rank, int ranks) {
  return total * static_cast<std::uint64_t>(rank) / static_cast<std::uint64_t>(ranks);
}

ParticleShare read_sphp_run(const std::filesystem::path& path, int rank, int ranks,
                            std::uint64_t& hash) {
  const SphpFile in(path);
  ParticleShare share;
  share.total = in.count();
  hash = sample_hash(in);
  in.read(run_start(share.total, rank, ranks), run_start(share.total, rank + 1, ranks),
          share.spheres, &share.ids);
  return share;
}

// Any other particle file (text, PLY, PDB) has no offsets to read a run at: every rank reads
// the whole file and keeps its run. A .sphp file (`sphray convert`) is the format for many
// ranks. The hash covers the count and the same sample of particles as a .sphp file's.
ParticleShare read_other_run(const std::filesystem::path& path, int rank, int ranks,
                             std::uint64_t& hash) {
  const particles::Points all = particles::read_particle_file(path);
  const SphereView v = all.spheres.view();
  ParticleShare share;
  share.total = v.count;
  Fnv1a sample;
  sample.add(&share.total, sizeof share.total);
  const std::uint64_t samples = std::min<std::uint64_t>(v.count, kSampleRecords);
  for (std::uint64_t k = 0; k < samples; ++k) {
    const std::size_t i = v.count * k / samples;
    const float record[4] = {v.cx[i], v.cy[i], v.cz[i], v.radius[i]};
    sample.add(record, sizeof record);
  }
  hash = sample.value();
  const std::uint64_t first = run_start(v.count, rank, ranks);
  const std::uint64_t end = run_start(v.count, rank + 1, ranks);
  share.spheres.reserve(end - first);
  share.ids.reserve(end - first);
  for (std::uint64_t i = first; i < end; ++i) {
    share.spheres.add({v.cx[i], v.cy[i], v.cz[i]}, v.radius[i]);
    share.ids.push_back(static_cast<std::uint32_t>(i));
  }
  return share;
}

// A file of another format by its extension is read whole; any other file is taken for a .sphp
// file, whatever its name, as before other formats were read, and refused by its header if not.
ParticleShare read_run(const std::filesystem::path& path, int rank, int ranks,
                       std::uint64_t& hash) {
  const bool other = particles::is_particle_file(path) && !SphpFile::named(path);
  return other ? read_other_run(path, rank, ranks, hash) : read_sphp_run(path, rank, ranks, hash);
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
