// The particle file (.sphp, sphray/particles/particles.hpp has its layout), read by every rank
// of a job in parallel, each its own part, without reading the rest. The format, its checks and
// its encoder live in sphray::particles; this is the collective read and the Morton-ordered
// writer.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sphray/particles/particles.hpp"
#include "sphray/sphray.hpp"

namespace sphray::mpi {

/// A file that cannot be read as a particle file; what() is one line naming the file.
using ParticleFileError = particles::ParticleError;

/// One rank's run of a particle file: its spheres and their ids (ascending, consecutive).
struct ParticleShare {
  SphereSoA spheres;
  std::vector<std::uint32_t> ids;
  std::uint64_t total = 0;  // particles in the whole file
};

/// Rank r of p reads particles [total * r / p, total * (r + 1) / p) of a .sphp file, without
/// reading the rest. Any other particle file sphray::particles reads (text, and the formats
/// read_particle_file adds) is read whole by every rank, which keeps its run. Only a regular file
/// is read (a FIFO or a device is refused at once, never waited on). Collective over comm: the
/// ranks agree on the outcome, so when any of them cannot read its part every rank throws
/// ParticleFileError with the lowest such rank's message, and none is left waiting. The ranks
/// also compare the particle count and a hash of the header and of 256 records spread over the
/// file, and every rank throws if they differ: the ranks read different files.
ParticleShare read_particle_share(MPI_Comm comm, const std::filesystem::path& file);

/// Receives a file's bytes, in order, a piece at a time; throws to stop the writing.
using ByteSink = particles::ByteSink;

/// The particle file of spheres, in Morton order of their centres (the ids in the file are then
/// positions in that order, not spheres' ids), given to sink in pieces of at most 1 MiB. Throws
/// ParticleFileError for 2^32 - 1 spheres or more (before any byte); what sink throws passes
/// through. To write a file, give a sink that writes a temporary file renamed over the target
/// once complete, so that a failure never destroys the file replaced (sphray-mpi generate uses
/// the renderer's atomic output).
void write_particles(const ByteSink& sink, SphereView spheres);

}  // namespace sphray::mpi
