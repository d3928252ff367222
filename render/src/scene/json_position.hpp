// Where things are in a scene file's text, found only when a refusal needs a position.
//
// nlohmann_json 3.11 keeps no source positions in its values, so the checks run on the parsed
// document and, only when one fails, a SAX pass over the text finds where the offending value
// (or key) starts. Every pass here takes memory linear in the text: the path of the value being
// read is kept once, as one string that grows and shrinks with the nesting, never per level.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace sphray::render::json_position {

/// "line:column" of a byte offset: lines counted from 1 at each '\n', columns in characters
/// (UTF-8 sequences count once) from 1, a UTF-8 byte order mark at the start not counted.
std::string line_column(std::string_view text, std::size_t offset);

/// The start of the token that ends at or just before `read` bytes (the parser's position
/// after reading it: a number is finished by one character of lookahead).
std::size_t token_start(std::string_view text, std::size_t read);

/// Where the value at a JSON pointer (keys unescaped; matched, never resolved) starts, or,
/// with at_key, where its key starts: the first occurrence in document order. "1:1"-style
/// offset 0 if it is not found.
std::size_t find_pointer(std::string_view text, const std::string& pointer, bool at_key);

/// The first key that repeats a key earlier in the same object: where it starts and its name.
struct DuplicateKey {
  std::size_t offset;
  std::string key;
};
std::optional<DuplicateKey> find_duplicate_key(std::string_view text);

/// Where the first '[' or '{' that opens a level deeper than max_depth is, outside strings, or
/// nothing. One pass over the bytes, no allocation: run before the parser builds anything.
std::optional<std::size_t> find_nesting_beyond(std::string_view text, std::size_t max_depth);

/// Where a SAX pass over the text first fails (for errors json::parse reports without a
/// position, such as a number beyond double's range).
std::size_t first_error(std::string_view text);

}  // namespace sphray::render::json_position
