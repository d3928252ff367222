// What the particle readers share: quoting a field for a one-line message, number parsing as
// the text reader does it, the checks every particle passes, and opening only regular files.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "sphray/particles/particles.hpp"

namespace sphray::particles::detail {

// Coordinates and radii at most this in magnitude: their squares (and the kernel's products of
// them) stay far inside float's range, as for scene files.
inline constexpr float kMaxMagnitude = 1e17f;

/// A field quoted for a message: at most 40 bytes, bytes outside printable ASCII as \xHH, so
/// that the message stays one line whatever the file holds.
std::string quoted(std::string_view field);
/// ASCII letters lowered (file extensions, column names).
std::string lower(std::string_view text);
/// The shortest text that reads back as value.
std::string shortest(float value);
std::string shortest(double value);
/// s without blanks (not '\n') at either end.
std::string_view trim(std::string_view s);
/// field as a float as C writes it ("+.5" too); out_of_range tells a number too large for float
/// from one that is not a number.
std::optional<float> as_number(std::string_view field, bool& out_of_range);
/// The same as a double.
std::optional<double> as_double(std::string_view field, bool& out_of_range);

/// What is wrong with value as a particle's coordinate (or radius, when radius): "to be finite",
/// "to be positive" or "at most 1e17 in magnitude" for a message, or null when nothing is.
const char* coordinate_problem(float value, bool radius);
/// Throws ParticleError naming source when options carry a radius outside (0, 1e17].
void check_radius_option(const std::string& source, const PointOptions& options);

/// A file descriptor closed when the reading ends, however it ends.
struct Closing {
  int fd;
  ~Closing();
};

/// path opened for reading, refused (ParticleError) unless it is a regular file; size is set to
/// its size. A FIFO is refused at once, never waited on.
int open_regular(const std::filesystem::path& path, std::uint64_t& size);
/// Up to size bytes from fd into data (fewer only at the end of the file); ParticleError naming
/// source on a read error.
std::size_t read_some(int fd, char* data, std::size_t size, const std::string& source);

}  // namespace sphray::particles::detail
