// sphray::particles: spheres read from the files their owners have, in one library that the
// sphray command, sphray-mpi and (later) the C API and Python share. The kernel never reads
// files; this library does, and gives the kernel a SphereSoA.
//
// Formats (docs/scenes.md, "Particle files"):
//   .sphp        the binary particle file of docs/distributed.md (layout below);
//   .xyz, .csv   text points, one particle per line: x y z [r] [red green blue], separated by
//                whitespace or (when the first line that is not blank or a comment has a comma)
//                by commas; an optional header line naming the columns; '#' starts a comment;
//   .ply         PLY, ascii or binary of either byte order: the element vertex's x, y, z, radius
//                (or scale), red, green, blue; other elements and properties are read past.
//   .pdb, .ent   PDB atoms: the ATOM and HETATM records of the first model (up to the first
//                ENDMDL), in the PDB v3.3 fixed columns (x 31-38, y 39-46, z 47-54, element
//                77-78, else guessed from the atom name, 13-16); each atom a sphere of its
//                element's van der Waals radius (Bondi 1964, Mantina et al. 2009 for the
//                main-group elements Bondi lacks, 2.00 angstroms for the others) and Jmol's CPK
//                colour. Every other record is ignored; a symbol that is no element is refused.
//
// Every reader refuses a bad file with a ParticleError whose what() is one line naming the
// file, the line (text, a PLY header or ascii body) or the particle and its byte offset
// (binary), and the problem.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "sphray/sphray.hpp"

namespace sphray::particles {

/// A file that cannot be read as particles; what() is one line naming the file.
class ParticleError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Particles in one file at most: ids 0 to 2^32 - 2 (kNoHit is no id).
inline constexpr std::uint64_t kMaxParticles = kNoHit;

// --- The binary particle file (.sphp) ------------------------------------------------------
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
// together (sphray::mpi::write_particles uses a Morton curve), so that the equal runs of
// particles that ranks read are compact regions of space.
inline constexpr std::size_t kSphpHeaderBytes = 32;
inline constexpr std::size_t kSphpRecordBytes = 16;

/// An open particle file whose header and size have been checked. Reads use pread at offsets
/// (not a memory map: a file truncated under a map kills the reader with SIGBUS, where a read
/// reports "truncated while reading"). Only a regular file is opened (a FIFO or a device is
/// refused at once, never waited on).
class SphpFile {
 public:
  /// Throws ParticleError: cannot open, not a regular file, a bad header, a size that is not
  /// the header's.
  explicit SphpFile(const std::filesystem::path& path);
  ~SphpFile();
  SphpFile(const SphpFile&) = delete;
  SphpFile& operator=(const SphpFile&) = delete;

  /// Whether path's extension is .sphp (any case).
  static bool named(const std::filesystem::path& path);

  std::uint64_t count() const { return count_; }
  const std::filesystem::path& path() const { return path_; }
  /// Exactly n bytes at offset, or a ParticleError.
  void read_bytes(void* out, std::size_t n, std::uint64_t offset) const;
  /// Appends particles [first, end) to spheres, reading 1 MiB at a time; when ids is not null,
  /// appends each particle's index too.
  void read(std::uint64_t first, std::uint64_t end, SphereSoA& spheres,
            std::vector<std::uint32_t>* ids = nullptr) const;

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  std::uint64_t count_ = 0;
};

/// Every particle of a particle file, sphere id = index in the file. Throws ParticleError.
SphereSoA read_sphp(const std::filesystem::path& path);

/// Receives a file's bytes, in order, a piece at a time; throws to stop the writing.
using ByteSink = std::function<void(const void* data, std::size_t size)>;

/// Throws ParticleError when count particles cannot be one file (2^32 - 1 or more).
void check_particle_count(std::uint64_t count);

/// The particle file of spheres, record k being sphere order[k] (every sphere in index order
/// when order is empty), given to sink in pieces of at most 1 MiB. Throws ParticleError for
/// 2^32 - 1 spheres or more (before any byte); what sink throws passes through.
void write_sphp(const ByteSink& sink, SphereView spheres,
                std::span<const std::uint32_t> order = {});

// --- Text points (.xyz, .csv) -------------------------------------------------------------

/// What the caller supplies that a file may lack.
struct PointOptions {
  /// The radius of every particle of a file without a radius column (ignored for a file that
  /// has one). Positive, at most 1e17.
  std::optional<float> radius;
  /// Also keep every coordinate and radius as the file writes it, in double (Points::doubles):
  /// for a scene traced in double (`sphray render --precision double`). Text and PLY files
  /// are read again as doubles; .sphp (floats by format) and PDB (three decimals) have no more
  /// digits than their floats, and leave Points::doubles empty.
  bool keep_doubles = false;
};

/// Particles and, when the file has colour columns, one colour per particle in [0, 1].
struct Points {
  SphereSoA spheres;
  std::vector<Vec3> colors;  // empty when the file has none
  /// With PointOptions::keep_doubles, for text and PLY files: the same spheres as the file
  /// writes them, in double (spheres holds them rounded to float). Empty otherwise.
  SphereSoAd doubles;
};

/// The longest line a text file may have, in bytes (a line of seven floats needs about 120).
inline constexpr std::size_t kMaxLineBytes = 4096;

/// Text points read from file, a piece at a time (memory grows with the particles, not with
/// the text). Throws ParticleError "FILE:LINE: expected ..., got ...".
Points read_points(const std::filesystem::path& file, const PointOptions& options = {});
/// Text points parsed from text; source names it in messages. Throws ParticleError.
Points parse_points(std::string_view text, const std::string& source,
                    const PointOptions& options = {});

// --- PDB atoms (.pdb, .ent) -------------------------------------------------------------

/// The atoms of a PDB file's first model, read a line at a time (lines of at most
/// kMaxLineBytes): sphere i is the i-th ATOM or HETATM record, colours always present. Throws
/// ParticleError "FILE:LINE: expected ..., got ...".
Points read_pdb(const std::filesystem::path& file);
/// PDB atoms parsed from text; source names it in messages. Throws ParticleError.
Points parse_pdb(std::string_view text, const std::string& source);

// --- PLY (.ply) ---------------------------------------------------------------------------
//
// ascii 1.0, binary_little_endian 1.0 and binary_big_endian 1.0. The element vertex gives the
// particles, in file order: properties x, y, z, radius (or scale: a radius, not a logarithm),
// red, green, blue, each of any scalar type; integer colours are 0-255 (divided by 255), float
// colours 0-1. Every other element and property (lists too) is read past. An ascii body has one
// element a line, each line at most kMaxLineBytes.

/// PLY particles read from file through a 1 MiB buffer (memory grows with the particles, not
/// with the file). Throws ParticleError "FILE:LINE: expected ..." (header, ascii body) or
/// "FILE: byte OFFSET (ELEMENT INDEX): ..." (binary body).
Points read_ply(const std::filesystem::path& file, const PointOptions& options = {});
/// PLY particles parsed from bytes; source names it in messages. Throws ParticleError.
Points parse_ply(std::string_view bytes, const std::string& source,
                 const PointOptions& options = {});
/// A binary_little_endian PLY file of spheres (float x, y, z, radius) and, when colors is not
/// empty (one per sphere), uchar red, green, blue (each colour clamped to [0, 1] and rounded to
/// k / 255), given to sink in pieces of at most 1 MiB. Throws ParticleError for 2^32 - 1 spheres
/// or more, or a colour count that is not the spheres'; what sink throws passes through.
void write_ply(const ByteSink& sink, SphereView spheres, std::span<const Vec3> colors = {});

// --- Any particle file --------------------------------------------------------------------

/// Whether path names a particle file by its extension (.sphp, .xyz, .csv, .ply, .pdb, .ent;
/// any case).
bool is_particle_file(const std::filesystem::path& path);
/// The particles of a .sphp, .xyz, .csv, .ply, .pdb or .ent file, chosen by its extension (no
/// colours from .sphp; options apply to .xyz, .csv and .ply). Throws ParticleError.
Points read_particle_file(const std::filesystem::path& path, const PointOptions& options = {});

// --- Writing particle files -----------------------------------------------------------------

/// Text points of spheres, given to sink in pieces of at most 1 MiB: a header line naming the
/// columns (x y z radius, then red green blue when colors is not empty), then one line per
/// sphere, its fields separated by separator (' ' for .xyz, ',' for .csv). Every float is
/// written in the shortest text that reads back to the same bits, so read_points gives the
/// same spheres and colours, bit for bit. colors is empty or one per sphere, in [0, 1]. Throws
/// ParticleError for 2^32 - 1 spheres or more and std::invalid_argument for a colors of another
/// size (both before any byte); what sink throws passes through.
void write_points(const ByteSink& sink, SphereView spheres, std::span<const Vec3> colors,
                  char separator);

/// Throws ParticleError "PATH: expected an output particle file ending in ..." unless
/// write_particle_file writes the format path's extension names (.sphp, .xyz, .csv; any case).
void check_particle_output(const std::filesystem::path& path);

/// The particle file of spheres in the format path's extension names: .sphp (write_sphp, no
/// colours), .xyz or .csv (write_points, colours when given). path only chooses the format and
/// names the file in messages; the bytes go to sink. Throws as check_particle_output (before any
/// byte) and as the writers do.
void write_particle_file(const ByteSink& sink, const std::filesystem::path& path,
                         SphereView spheres, std::span<const Vec3> colors = {});

}  // namespace sphray::particles
