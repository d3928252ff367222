// The particle file: spheres in a flat binary file that every rank of a job reads its own part
// of, in parallel, without reading the rest.
//
//   bytes 0-7    magic "SPHRAYP\0"
//   bytes 8-11   version, uint32 little-endian: 1
//   bytes 12-15  zero (reserved)
//   bytes 16-23  count, uint64 little-endian: the number of particles, below 2^32 - 1
//   bytes 24-31  zero (reserved)
//   then count records of 16 bytes: x, y, z, r as float32 little-endian
//
// Particle i (from 0, in file order) is sphere id i. The file is exactly 32 + 16 * count bytes;
// anything else is refused. Writers should store particles in an order that keeps neighbours
// together (write_particles uses a Morton curve), so that the equal runs of particles the ranks
// read are compact regions of space.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sphray/sphray.hpp"

namespace sphray::mpi {

/// A file that cannot be read as a particle file; what() is one line naming the file.
class ParticleFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One rank's run of a particle file: its spheres and their ids (ascending, consecutive).
struct ParticleShare {
  SphereSoA spheres;
  std::vector<std::uint32_t> ids;
  std::uint64_t total = 0;  // particles in the whole file
};

/// Rank r of p reads particles [total * r / p, total * (r + 1) / p). Only a regular file is
/// read (a FIFO or a device is refused at once, never waited on). Collective over comm: the
/// ranks agree on the outcome, so when any of them cannot read its part every rank throws
/// ParticleFileError with the lowest such rank's message, and none is left waiting. The ranks
/// also compare the particle count and a hash of the header and of 256 records spread over the
/// file, and every rank throws if they differ: the ranks read different files.
ParticleShare read_particle_share(MPI_Comm comm, const std::filesystem::path& file);

/// Receives a file's bytes, in order, a piece at a time; throws to stop the writing.
using ByteSink = std::function<void(const void* data, std::size_t size)>;

/// The particle file of spheres, in Morton order of their centres (the ids in the file are then
/// positions in that order, not spheres' ids), given to sink in pieces of at most 1 MiB. Throws
/// ParticleFileError for 2^32 - 1 spheres or more (before any byte); what sink throws passes
/// through. To write a file, give a sink that writes a temporary file renamed over the target
/// once complete, so that a failure never destroys the file replaced (sphray-mpi generate uses
/// the renderer's atomic output).
void write_particles(const ByteSink& sink, SphereView spheres);

}  // namespace sphray::mpi
