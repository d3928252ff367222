// What the line-based readers (.xyz/.csv points, .pdb atoms) share: a file read a line at a time
// through a fixed buffer (memory never grows with the text) and the same text split from memory
// (for tests and fuzzers). The helpers every reader uses are in support.hpp.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

#include "support.hpp"

namespace sphray::particles::detail {

/// Receives one line, without its '\n', and its 1-based number; returns false to read no further
/// (the PDB reader stops at the end of the first model).
using LineSink = std::function<bool(std::string_view line, std::uint64_t number)>;

/// Every line of a regular file, in order, read a piece at a time, until sink returns false.
/// Throws ParticleError: cannot open, not a regular file, a line longer than kMaxLineBytes.
void read_lines(const std::filesystem::path& file, const LineSink& sink);
/// Every line of text, as read_lines gives a file's (until sink returns false); source names it in
/// messages.
void split_lines(std::string_view text, const std::string& source, const LineSink& sink);

}  // namespace sphray::particles::detail
