#include "scene/json_position.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <vector>

namespace sphray::render::json_position {
namespace {

using nlohmann::json;

// An input iterator for nlohmann's SAX parser that counts the bytes read so far.
class CountingIterator {
 public:
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  CountingIterator(const char* p, const char* base, std::size_t* read)
      : p_(p), base_(base), read_(read) {}
  reference operator*() const { return *p_; }
  CountingIterator& operator++() {
    ++p_;
    *read_ = static_cast<std::size_t>(p_ - base_);
    return *this;
  }
  CountingIterator operator++(int) {
    CountingIterator old = *this;
    ++*this;
    return old;
  }
  bool operator==(const CountingIterator& other) const { return p_ == other.p_; }

 private:
  const char* p_;
  const char* base_;
  std::size_t* read_;
};

// Runs handler over text as nlohmann's SAX parser, with read counting the bytes it consumed.
template <class Handler>
void sax_over(std::string_view text, Handler& handler, std::size_t& read) {
  CountingIterator first(text.data(), text.data(), &read);
  CountingIterator last(text.data() + text.size(), text.data(), &read);
  json::sax_parse(first, last, &handler);
}

// A SAX handler that accepts everything; the finders override what they look at.
class NullHandler : public nlohmann::json_sax<json> {
 public:
  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(false); }
  bool start_array(std::size_t) override { return open(true); }
  bool end_object() override { return close(); }
  bool end_array() override { return close(); }
  bool key(string_t&) override { return true; }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
    return false;
  }

 protected:
  virtual bool value() { return true; }
  virtual bool open(bool) { return true; }
  virtual bool close() { return true; }
};

// Notes how far the parser had read when it finished the key or the value at one JSON pointer.
//
// The path is kept as one string: path_ is the path of the innermost open container, and each
// level remembers only the length path_ had before it (to cut back on close) and its array
// index. A path per level (as this once kept) costs the square of the depth: 1.6 GB for an
// 80 KB file nested 40,000 deep.
class PointerFinder : public NullHandler {
 public:
  PointerFinder(const std::string& target, bool at_key, const std::size_t& read)
      : target_(target), at_key_(at_key), read_(read) {}
  std::optional<std::size_t> found() const { return found_; }

  bool key(string_t& name) override {
    key_ = name;
    if (at_key_ && here_is_target()) found_ = read_;
    return !found_;
  }

 private:
  struct Level {
    std::size_t path_length;  // path_'s length before this container's own segment
    bool is_array;
    std::size_t index;
  };

  // The segment of the value about to be read, in the innermost container.
  void segment(std::string& out) const {
    if (levels_.empty()) return;
    out += '/';
    if (levels_.back().is_array) {
      out += std::to_string(levels_.back().index);
    } else {
      out += key_;
    }
  }
  bool here_is_target() {
    scratch_.clear();
    segment(scratch_);
    // Compare lengths first: almost every value's path differs from the target in length.
    return path_.size() + scratch_.size() == target_.size() &&
           target_.compare(0, path_.size(), path_) == 0 &&
           target_.compare(path_.size(), std::string::npos, scratch_) == 0;
  }
  void next_element() {
    if (!levels_.empty() && levels_.back().is_array) ++levels_.back().index;
  }

  bool value() override {
    if (!at_key_ && here_is_target()) found_ = read_;
    next_element();
    return !found_;
  }
  bool open(bool is_array) override {
    if (!at_key_ && here_is_target()) found_ = read_;
    const std::size_t before = path_.size();
    segment(path_);
    levels_.push_back({before, is_array, 0});
    return !found_;
  }
  bool close() override {
    path_.resize(levels_.back().path_length);
    levels_.pop_back();
    next_element();
    return true;
  }

  const std::string& target_;
  bool at_key_;
  const std::size_t& read_;
  std::string path_;
  std::string key_;
  std::string scratch_;
  std::vector<Level> levels_;
  std::optional<std::size_t> found_;
};

// Finds the first key repeated within one object. Each open object keeps the set of its keys,
// which together hold at most the keys of the text: linear.
class DuplicateFinder : public NullHandler {
 public:
  explicit DuplicateFinder(const std::size_t& read) : read_(read) {}
  const std::optional<DuplicateKey>& found() const { return found_; }

  bool key(string_t& name) override {
    if (!objects_.back().insert(name).second) found_ = DuplicateKey{read_, name};
    return !found_;
  }

 private:
  bool open(bool is_array) override {
    if (!is_array) objects_.emplace_back();
    kinds_.push_back(is_array);
    return true;
  }
  bool close() override {
    if (!kinds_.back()) objects_.pop_back();
    kinds_.pop_back();
    return true;
  }

  const std::size_t& read_;
  std::vector<std::set<std::string>> objects_;
  std::vector<bool> kinds_;  // per open container: an array?
  std::optional<DuplicateKey> found_;
};

class FirstError : public NullHandler {
 public:
  std::size_t offset() const { return offset_; }
  bool parse_error(std::size_t position, const std::string&,
                   const nlohmann::detail::exception&) override {
    offset_ = position > 0 ? position - 1 : 0;
    return false;
  }

 private:
  std::size_t offset_ = 0;
};

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

bool is_utf8_continuation(char c) {
  return (static_cast<unsigned char>(c) & 0xc0u) == 0x80u;
}

constexpr std::string_view kByteOrderMark = "\xef\xbb\xbf";

}  // namespace

std::size_t token_start(std::string_view text, std::size_t read) {
  std::size_t last = std::min(read, text.size());
  // A number is finished by one character of lookahead: whitespace or a delimiter.
  while (last > 0 && (is_space(text[last - 1]) || std::strchr(",:]}", text[last - 1]) != nullptr)) {
    --last;
  }
  if (last == 0) return 0;
  std::size_t i = last - 1;
  if (text[i] == '{' || text[i] == '[') return i;
  if (text[i] == '"') {
    for (std::size_t j = i; j-- > 0;) {
      if (text[j] == '"' && (j == 0 || text[j - 1] != '\\')) return j;
    }
    return 0;
  }
  while (i > 0 && (std::isalnum(static_cast<unsigned char>(text[i - 1])) || text[i - 1] == '.' ||
                   text[i - 1] == '+' || text[i - 1] == '-')) {
    --i;
  }
  return i;
}

std::string line_column(std::string_view text, std::size_t offset) {
  std::size_t line = 1, column = 1;
  std::size_t start = text.starts_with(kByteOrderMark) ? kByteOrderMark.size() : 0;
  for (std::size_t i = start; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else if (!is_utf8_continuation(text[i])) {
      ++column;
    }
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

std::size_t find_pointer(std::string_view text, const std::string& pointer, bool at_key) {
  if (pointer.empty() && !at_key) return 0;
  std::size_t read = 0;
  PointerFinder finder(pointer, at_key, read);
  sax_over(text, finder, read);
  return finder.found() ? token_start(text, *finder.found()) : 0;
}

std::optional<DuplicateKey> find_duplicate_key(std::string_view text) {
  std::size_t read = 0;
  DuplicateFinder finder(read);
  sax_over(text, finder, read);
  std::optional<DuplicateKey> found = finder.found();
  if (found) found->offset = token_start(text, found->offset);
  return found;
}

std::optional<std::size_t> find_nesting_beyond(std::string_view text, std::size_t max_depth) {
  std::size_t depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::nullopt;
}

std::size_t first_error(std::string_view text) {
  FirstError where;
  json::sax_parse(text, &where);
  return token_start(text, where.offset() + 1);
}

}  // namespace sphray::render::json_position
