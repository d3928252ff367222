// What the text readers (.xyz/.csv points, .pdb atoms) share: a file read a line at a time
// through a fixed buffer (memory never grows with the text), the same text split from memory
// (for tests and fuzzers), and the helpers that keep their messages one line.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace sphray::particles::detail {

/// Coordinates and radii at most this in magnitude: their squares (and the kernel's products of
/// them) stay far inside float's range, as for scene files.
inline constexpr float kMaxMagnitude = 1e17f;

/// Receives one line, without its '\n', and its 1-based number; returns false to read no further
/// (the PDB reader stops at the end of the first model).
using LineSink = std::function<bool(std::string_view line, std::uint64_t number)>;

/// Every line of a regular file, in order, read a piece at a time, until sink returns false.
/// Throws ParticleError: cannot open, not a regular file, a line longer than kMaxLineBytes.
void read_lines(const std::filesystem::path& file, const LineSink& sink);
/// Every line of text, as read_lines gives a file's (until sink returns false); source names it in
/// messages.
void split_lines(std::string_view text, const std::string& source, const LineSink& sink);

/// A field quoted for a message: at most 40 bytes, bytes outside printable ASCII as \xHH, so
/// that the message stays one line whatever the file holds.
std::string quoted(std::string_view field);
/// ASCII lower case.
std::string lower(std::string_view text);
/// The shortest text that reads back as value.
std::string shortest(float value);
/// Without leading and trailing blanks (space, tab, CR, VT, FF).
std::string_view trim(std::string_view s);
/// The number C would read from the whole field (a leading '+' allowed), or nothing;
/// out_of_range is set for a number beyond float's range.
std::optional<float> as_number(std::string_view field, bool& out_of_range);

}  // namespace sphray::particles::detail
