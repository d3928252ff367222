// PLY (.ply): the header a line at a time, then the body (ascii lines, or binary values of
// either byte order) through one 1 MiB buffer; the vertex element gives the particles, every
// other element and property is read past. Every refusal is one line naming the file and the
// line (header, ascii body) or the byte offset (binary body).
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

#include "sphray/particles/particles.hpp"
#include "support.hpp"

namespace sphray::particles {
namespace {

constexpr std::size_t kBufferBytes = std::size_t{1} << 20;

enum class Format { kAscii, kLittleEndian, kBigEndian };

// The scalar types, in the order of kTypes.
enum class Type { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

struct TypeName {
  std::string_view name, alias;
  std::size_t size;
  double lo, hi;  // the range of an integer type
};
constexpr std::array<TypeName, 8> kTypes = {{
    {"char", "int8", 1, -128, 127},
    {"uchar", "uint8", 1, 0, 255},
    {"short", "int16", 2, -32768, 32767},
    {"ushort", "uint16", 2, 0, 65535},
    {"int", "int32", 4, -2147483648.0, 2147483647.0},
    {"uint", "uint32", 4, 0, 4294967295.0},
    {"float", "float32", 4, 0, 0},
    {"double", "float64", 8, 0, 0},
}};

const TypeName& info(Type t) {
  return kTypes[static_cast<std::size_t>(t)];
}
bool is_integer(Type t) {
  return t < Type::kFloat32;
}

// What a property of the vertex element gives its particle.
enum Role { kX, kY, kZ, kRadius, kRed, kGreen, kBlue, kRoles, kSkip = kRoles };
constexpr std::array<std::string_view, kRoles> kRoleNames = {"x",   "y",     "z",   "radius",
                                                             "red", "green", "blue"};

struct Property {
  std::string name;
  Type type = Type::kFloat32;  // of the items, for a list
  bool list = false;
  Type count_type = Type::kUint8;
  Role role = kSkip;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t line = 0;  // where the header declares it
  std::vector<Property> properties;
};

// The bytes of a file or of memory, through one buffer.
class Input {
 public:
  // Fills up to size bytes; fewer only at the end of the input.
  using Fill = std::function<std::size_t(char* data, std::size_t size)>;

  // A buffer of 1 MiB, or less for a smaller input, but always room for a line longer than the
  // longest allowed (which line() needs to tell one that is too long).
  Input(Fill fill, std::uint64_t size)
      : fill_(std::move(fill)),
        buffer_(static_cast<std::size_t>(
            std::clamp<std::uint64_t>(size + 1, 2 * kMaxLineBytes, kBufferBytes))) {}

  /// Bytes consumed so far.
  std::uint64_t offset() const { return base_ + pos_; }

  /// The next n bytes, fewer only at the end or when n is more than the buffer holds (never
  /// fewer than 8192); valid until the next call.
  std::string_view peek(std::size_t n) {
    if (end_ - pos_ < n && !done_) refill();
    return {buffer_.data() + pos_, std::min(n, end_ - pos_)};
  }
  void skip(std::size_t n) { pos_ += n; }

  /// The next line without its '\n', nullopt at the end; too_long when it has more than max
  /// bytes. Valid until the next call.
  std::optional<std::string_view> line(std::size_t max, bool& too_long) {
    too_long = false;
    for (;;) {
      const std::string_view held(buffer_.data() + pos_, end_ - pos_);
      const std::size_t newline = held.find('\n');
      too_long = std::min(newline, held.size()) > max;
      if (too_long) return std::nullopt;
      if (newline != std::string_view::npos || done_) {
        if (held.empty()) return std::nullopt;
        pos_ += newline == std::string_view::npos ? held.size() : newline + 1;
        return held.substr(0, newline);
      }
      refill();
    }
  }

 private:
  // Moves the unread bytes to the front and reads after them.
  void refill() {
    std::memmove(buffer_.data(), buffer_.data() + pos_, end_ - pos_);
    base_ += pos_;
    end_ -= pos_;
    pos_ = 0;
    const std::size_t wanted = buffer_.size() - end_;
    const std::size_t got = fill_(buffer_.data() + end_, wanted);
    end_ += got;
    done_ = got < wanted;
  }

  Fill fill_;
  std::vector<char> buffer_;
  std::size_t pos_ = 0, end_ = 0;
  std::uint64_t base_ = 0;  // offset of buffer_[0]
  bool done_ = false;
};

// The blank-separated words of text into out (reused: this runs for every ascii line).
void split_words(std::string_view text, std::vector<std::string_view>& out) {
  out.clear();
  text = detail::trim(text);
  while (!text.empty()) {
    const std::size_t end = text.find_first_of(" \t\r\v\f");
    out.push_back(text.substr(0, end));
    text = detail::trim(text.substr(std::min(end, text.size())));
  }
}

std::optional<Type> type_named(std::string_view name) {
  for (std::size_t i = 0; i < kTypes.size(); ++i) {
    if (name == kTypes[i].name || name == kTypes[i].alias) return static_cast<Type>(i);
  }
  return std::nullopt;
}

// a * b + c, or the largest uint64 when that overflows (a size no file has).
std::uint64_t saturating_madd(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
  if (b != 0 && a > (kMax - c) / b) return kMax;
  return a * b + c;
}

// A binary value: n bytes in the file's order, as the type says.
double decode(const char* bytes, Type type, bool big_endian) {
  const std::size_t n = info(type).size;
  std::uint64_t raw = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const auto byte = static_cast<unsigned char>(bytes[big_endian ? k : n - 1 - k]);
    raw = raw << 8 | byte;
  }
  switch (type) {
    case Type::kInt8:
      return static_cast<std::int8_t>(raw);
    case Type::kUint8:
      return static_cast<std::uint8_t>(raw);
    case Type::kInt16:
      return static_cast<std::int16_t>(raw);
    case Type::kUint16:
      return static_cast<std::uint16_t>(raw);
    case Type::kInt32:
      return static_cast<std::int32_t>(raw);
    case Type::kUint32:
      return static_cast<std::uint32_t>(raw);
    case Type::kFloat32:
      return std::bit_cast<float>(static_cast<std::uint32_t>(raw));
    case Type::kFloat64:
      return std::bit_cast<double>(raw);
  }
  return 0;
}

// An element of the body, named for a message ("vertex 17") only when one is made.
struct Item {
  const Element& element;
  std::uint64_t index;
  std::string name() const { return element.name + " " + std::to_string(index); }
};

// The reader: the header, the check that its counts fit the file, then the body.
class PlyReader {
 public:
  PlyReader(std::string source, const PointOptions& options, Input& input, std::uint64_t size)
      : source_(std::move(source)), options_(options), input_(input), size_(size) {
    detail::check_radius_option(source_, options);
  }

  Points read() {
    header();
    check_vertex();
    check_sizes();
    points_.spheres.reserve(vertex().count);
    if (has_[kRed]) points_.colors.reserve(vertex().count);
    for (std::size_t e = 0; e < elements_.size(); ++e) {
      if (elements_[e].properties.empty()) continue;  // nothing to read, however many
      for (std::uint64_t i = 0; i < elements_[e].count; ++i) {
        if (format_ == Format::kAscii) {
          ascii_element(elements_[e], i, e == vertex_);
        } else {
          binary_element(elements_[e], i, e == vertex_);
        }
      }
    }
    check_end();
    return std::move(points_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { fail_at(line_, what); }
  [[noreturn]] void fail_at(std::uint64_t line, const std::string& what) const {
    throw ParticleError(source_ + ":" + std::to_string(line) + ": expected " + what);
  }
  [[noreturn]] void fail_byte(std::uint64_t offset, const std::string& where,
                              const std::string& what) const {
    throw ParticleError(source_ + ": byte " + std::to_string(offset) +
                        (where.empty() ? "" : " (" + where + ")") + ": " + what);
  }
  const Element& vertex() const { return elements_[vertex_]; }

  // The next line of the file, counted; nullopt at the end.
  std::optional<std::string_view> next_line() {
    bool too_long = false;
    const std::optional<std::string_view> text = input_.line(kMaxLineBytes, too_long);
    ++line_;
    if (too_long) fail("lines of at most " + std::to_string(kMaxLineBytes) + " bytes");
    return text;
  }

  // --- The header ---------------------------------------------------------------------------

  void header() {
    const std::optional<std::string_view> first = next_line();
    if (!first || detail::trim(*first) != "ply")
      fail("'ply' (the first line of a PLY file), got " + detail::quoted(first.value_or("")));
    for (;;) {
      const std::optional<std::string_view> text = next_line();
      if (!text) fail("'end_header', got the end of the file");
      split_words(*text, fields_);
      const std::vector<std::string_view>& w = fields_;
      const std::string_view key = w.empty() ? std::string_view() : w[0];
      if (key == "comment" || key == "obj_info") continue;
      if (key == "format") {
        format(w, *text);
      } else if (key == "element") {
        element(w, *text);
      } else if (key == "property") {
        property(w, *text);
      } else if (key == "end_header" && w.size() == 1) {
        if (!format_seen_) fail("a 'format' line before 'end_header'");
        return;
      } else {
        fail("'element', 'property', 'comment', 'obj_info' or 'end_header', got " +
             detail::quoted(*text));
      }
    }
  }

  void format(const std::vector<std::string_view>& w, std::string_view text) {
    if (format_seen_ || !elements_.empty()) fail("one 'format' line, before the elements");
    const std::string_view name = w.size() == 3 && w[2] == "1.0" ? w[1] : std::string_view();
    if (name == "ascii") {
      format_ = Format::kAscii;
    } else if (name == "binary_little_endian") {
      format_ = Format::kLittleEndian;
    } else if (name == "binary_big_endian") {
      format_ = Format::kBigEndian;
    } else {
      fail(
          "'format ascii 1.0', 'format binary_little_endian 1.0' or 'format "
          "binary_big_endian 1.0', got " +
          detail::quoted(text));
    }
    format_seen_ = true;
  }

  void element(const std::vector<std::string_view>& w, std::string_view text) {
    if (!format_seen_) fail("a 'format' line before the elements");
    std::uint64_t count = 0;
    bool counted = false;
    if (w.size() == 3) {
      const char* end = w[2].data() + w[2].size();
      const auto parsed = std::from_chars(w[2].data(), end, count);
      counted = parsed.ec == std::errc{} && parsed.ptr == end;
    }
    if (!counted) fail("'element NAME COUNT', got " + detail::quoted(text));
    if (w[1] == "vertex") {
      if (vertex_ != kNoVertex) fail("one element vertex, got a second");
      vertex_ = elements_.size();
    }
    elements_.push_back({std::string(w[1]), count, line_, {}});
  }

  void property(const std::vector<std::string_view>& w, std::string_view text) {
    if (elements_.empty())
      fail("'element NAME COUNT' before 'property', got " + detail::quoted(text));
    Property p;
    const bool list = w.size() == 5 && w[1] == "list";
    if (!list && w.size() != 3) {
      fail("'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME', got " +
           detail::quoted(text));
    }
    p.list = list;
    p.name = w.back();
    p.type = type_of(w[list ? 3 : 1]);
    if (list) {
      p.count_type = type_of(w[2]);
      if (!is_integer(p.count_type))
        fail("an integer type for the count of list " + p.name + ", got " + detail::quoted(w[2]));
    }
    Element& e = elements_.back();
    for (const Property& other : e.properties) {
      if (other.name == p.name)
        fail("each property of element " + e.name + " named once, got " + detail::quoted(p.name) +
             " twice");
    }
    if (elements_.size() - 1 == vertex_) p.role = role_of(p);
    e.properties.push_back(std::move(p));
  }

  Type type_of(std::string_view name) const {
    const std::optional<Type> type = type_named(name);
    if (!type) {
      fail(
          "a PLY type (char, uchar, short, ushort, int, uint, float, double or int8, uint8, "
          "int16, uint16, int32, uint32, float32, float64), got " +
          detail::quoted(name));
    }
    return *type;
  }

  // A vertex property's role: x, y, z, radius (or scale), red, green, blue, or none.
  Role role_of(const Property& p) {
    const std::string_view name = p.name == "scale" ? "radius" : std::string_view(p.name);
    const auto* known = std::find(kRoleNames.begin(), kRoleNames.end(), name);
    if (known == kRoleNames.end()) return kSkip;
    const auto role = static_cast<Role>(known - kRoleNames.begin());
    if (p.list) fail("property " + p.name + " of element vertex to be a scalar, got a list");
    if (has_[role]) fail("one of properties radius and scale in element vertex, got both");
    has_[role] = true;
    return role;
  }

  // The vertex element gives particles: x, y, z, a radius, colours in threes.
  void check_vertex() {
    if (vertex_ == kNoVertex) fail("an element vertex (the particles), the header has none");
    const std::uint64_t at = vertex().line;
    if (!has_[kX] || !has_[kY] || !has_[kZ]) fail_at(at, "properties x, y and z in element vertex");
    const int colours = has_[kRed] + has_[kGreen] + has_[kBlue];
    if (colours != 0 && colours != 3)
      fail_at(at, "properties red, green and blue in element vertex together, or none");
    if (!has_[kRadius] && !options_.radius) {
      fail_at(at,
              "a property radius (or scale) in element vertex, or a radius given for the file "
              "(sphray render --radius R)");
    }
    if (vertex().count >= kMaxParticles)
      fail_at(at, "at most 2^32 - 2 particles, got " + std::to_string(vertex().count));
    if (vertex().count == 0)
      throw ParticleError(source_ + ": expected particles, the file has none");
  }

  // Every element needs some bytes (binary: its scalars and list counts; ascii: a digit and a
  // separator per property): counts that cannot fit the file are refused before anything is
  // allocated for them.
  void check_sizes() const {
    const std::uint64_t body = size_ - std::min(size_, input_.offset());
    std::uint64_t need = 0;
    for (const Element& e : elements_) {
      std::uint64_t each = 0;
      for (const Property& p : e.properties)
        each += format_ == Format::kAscii ? 2 : info(p.list ? p.count_type : p.type).size;
      need = saturating_madd(e.count, each, need);
      // An ascii file's last line may lack its '\n'.
      if (need > body + (format_ == Format::kAscii)) {
        fail_at(e.line, std::to_string(e.count) + " " + e.name +
                            " elements to fit the file, at least " + std::to_string(need) +
                            " bytes after the header with those before, got " +
                            std::to_string(body));
      }
    }
  }

  // --- Values -------------------------------------------------------------------------------

  // A vertex property's value, checked, into the particle being read; what fails is given to
  // refuse as "to be ..." and the value as the file has it.
  template <typename Refuse>
  void take(const Property& p, double v, const Refuse& refuse) {
    if (p.role <= kRadius) {
      const bool radius = p.role == kRadius;
      const char* problem = !std::isfinite(v)    ? "to be finite"
                            : radius && !(v > 0) ? "to be positive"
                            : std::abs(v) > 1e17 ? "at most 1e17 in magnitude"
                                                 : nullptr;
      if (problem == nullptr) problem = detail::coordinate_problem(static_cast<float>(v), radius);
      if (problem != nullptr) refuse(problem);
      values_[p.role] = static_cast<float>(v);
      exact_[p.role] = v;  // a double property's digits, kept for PointOptions::keep_doubles
    } else if (is_integer(p.type)) {
      if (!(v >= 0 && v <= 255)) refuse("in 0 to 255 (an integer colour)");
      values_[p.role] = static_cast<float>(v) / 255.0f;  // as the text reader: 51 is 0.2f
    } else {
      if (!(v >= 0 && v <= 1)) refuse("in [0, 1] (a floating-point colour)");
      values_[p.role] = static_cast<float>(v);
    }
  }

  void add_particle() {
    if (has_[kRed]) points_.colors.push_back({values_[kRed], values_[kGreen], values_[kBlue]});
    const float radius = has_[kRadius] ? values_[kRadius] : *options_.radius;
    points_.spheres.add({values_[kX], values_[kY], values_[kZ]}, radius);
    if (options_.keep_doubles) {
      const double exact_radius = has_[kRadius] ? exact_[kRadius] : radius;
      points_.doubles.add(Vec3d{exact_[kX], exact_[kY], exact_[kZ]}, exact_radius);
    }
  }

  // --- The ascii body: one element a line -----------------------------------------------------

  std::optional<std::string_view> non_blank_line() {
    for (;;) {
      const std::optional<std::string_view> text = next_line();
      if (!text || !detail::trim(*text).empty()) return text;
    }
  }

  void ascii_element(const Element& e, std::uint64_t i, bool is_vertex) {
    const Item what{e, i};
    const std::optional<std::string_view> text = non_blank_line();
    if (!text) {
      fail(what.name() + " of " + std::to_string(e.count) +
           " (a line each), got the end of the file");
    }
    split_words(*text, fields_);
    std::size_t next = 0;
    const auto field = [&](const Property& p) {
      if (next == fields_.size())
        fail("a value for property " + p.name + " of " + what.name() + ", got the end of the line");
      return fields_[next++];
    };
    for (const Property& p : e.properties) {
      if (p.list) {
        const double n = ascii_value(p, p.count_type, field(p), what);
        if (n < 0) fail("property " + p.name + " of " + what.name() + " to have a count >= 0");
        for (double k = 0; k < n; ++k)
          ascii_value(p, p.type, field(p), what);
        continue;
      }
      const std::string_view token = field(p);
      const double v = ascii_value(p, p.type, token, what);
      if (is_vertex && p.role != kSkip) {
        take(p, v, [&](const char* problem) {
          fail("property " + p.name + " of " + what.name() + " " + problem + ", got " +
               detail::quoted(token));
        });
      }
    }
    if (next != fields_.size()) {
      fail("the line of " + what.name() + " to end after its " + std::to_string(next) +
           " values, got " + detail::quoted(fields_[next]));
    }
    if (is_vertex) add_particle();
  }

  // A token as a value of type; refused when it is not one.
  double ascii_value(const Property& p, Type type, std::string_view token, const Item& what) const {
    const auto refuse = [&](const std::string& problem) {
      fail("property " + p.name + " of " + what.name() + " " + problem + ", got " +
           detail::quoted(token));
    };
    bool range = false;
    if (type == Type::kFloat32) {
      const std::optional<float> v = detail::as_number(token, range);
      if (range) refuse("within float's range");
      if (!v) refuse("to be a number");
      return *v;
    }
    const std::optional<double> v = detail::as_double(token, range);
    if (range) refuse("within double's range");
    if (!v) refuse("to be a number");
    if (is_integer(type) && !(*v == std::floor(*v) && *v >= info(type).lo && *v <= info(type).hi))
      refuse("to be a " + std::string(info(type).name));
    return *v;
  }

  // --- The binary body ----------------------------------------------------------------------

  void binary_element(const Element& e, std::uint64_t i, bool is_vertex) {
    const auto where = [&] { return Item{e, i}.name(); };
    for (const Property& p : e.properties) {
      if (p.list) {
        const std::uint64_t at = input_.offset();
        const double n = binary_value(p.count_type, where);
        if (n < 0) {
          fail_byte(
              at, where(),
              "expected the count of list " + p.name + " to be >= 0, got " + detail::shortest(n));
        }
        skip_bytes(static_cast<std::uint64_t>(n) * info(p.type).size, where);
        continue;
      }
      const std::uint64_t at = input_.offset();
      const double v = binary_value(p.type, where);
      if (is_vertex && p.role != kSkip) {
        take(p, v, [&](const char* problem) {
          fail_byte(at, where(),
                    "expected property " + p.name + " " + problem + ", got " + detail::shortest(v));
        });
      }
    }
    if (is_vertex) add_particle();
  }

  template <typename Where>
  double binary_value(Type type, const Where& where) {
    const std::size_t n = info(type).size;
    const std::string_view bytes = input_.peek(n);
    if (bytes.size() < n) truncated(bytes.size(), n - bytes.size(), where());
    input_.skip(n);
    return decode(bytes.data(), type, format_ == Format::kBigEndian);
  }

  template <typename Where>
  void skip_bytes(std::uint64_t n, const Where& where) {
    while (n > 0) {
      const std::string_view bytes =
          input_.peek(static_cast<std::size_t>(std::min<std::uint64_t>(n, kBufferBytes)));
      if (bytes.empty()) truncated(0, n, where());
      input_.skip(bytes.size());
      n -= bytes.size();
    }
  }

  // The file ends held bytes after the current offset, missing bytes short.
  [[noreturn]] void truncated(std::size_t held, std::uint64_t missing, const std::string& where) {
    fail_byte(input_.offset() + held, where,
              "file ends, expected " + std::to_string(missing) + " more bytes");
  }

  // Nothing may follow the last element but (ascii) blank lines.
  void check_end() {
    if (format_ == Format::kAscii) {
      if (const std::optional<std::string_view> text = non_blank_line())
        fail("the end of the file after the last element, got " + detail::quoted(*text));
      return;
    }
    if (!input_.peek(1).empty()) {
      const std::uint64_t at = input_.offset();
      fail_byte(at, "",
                "expected the end of the file after the last element, got " +
                    std::to_string(size_ - std::min(size_, at)) + " more bytes");
    }
  }

  static constexpr std::size_t kNoVertex = std::numeric_limits<std::size_t>::max();

  std::string source_;
  PointOptions options_;
  Input& input_;
  std::uint64_t size_;
  std::uint64_t line_ = 0;
  Format format_ = Format::kAscii;
  bool format_seen_ = false;
  std::vector<Element> elements_;
  std::size_t vertex_ = kNoVertex;
  std::array<bool, kRoles> has_{};  // the vertex element's roles
  std::array<float, kRoles> values_{};
  std::array<double, kRadius + 1> exact_{};  // the coordinates and radius as the file has them
  std::vector<std::string_view> fields_;
  Points points_;
};

}  // namespace

Points parse_ply(std::string_view bytes, const std::string& source, const PointOptions& options) {
  // Pieces of the bytes, as a file's are read: the same code paths, buffer edges included.
  std::size_t at = 0;
  Input input(
      [&](char* data, std::size_t size) {
        const std::size_t n = std::min(size, bytes.size() - at);
        std::memcpy(data, bytes.data() + at, n);
        at += n;
        return n;
      },
      bytes.size());
  return PlyReader(source, options, input, bytes.size()).read();
}

Points read_ply(const std::filesystem::path& file, const PointOptions& options) {
  const std::string source = file.string();
  std::uint64_t size = 0;
  const detail::Closing fd{detail::open_regular(file, size)};
  Input input([&](char* data, std::size_t n) { return detail::read_some(fd.fd, data, n, source); },
              size);
  return PlyReader(source, options, input, size).read();
}

void write_ply(const ByteSink& sink, SphereView spheres, std::span<const Vec3> colors) {
  check_particle_count(spheres.count);
  if (!colors.empty() && colors.size() != spheres.count)
    throw ParticleError("expected one colour per sphere, or none");
  std::string header = "ply\nformat binary_little_endian 1.0\ncomment written by sphray\n";
  header += "element vertex " + std::to_string(spheres.count) + "\n";
  header += "property float x\nproperty float y\nproperty float z\nproperty float radius\n";
  if (!colors.empty()) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  header += "end_header\n";
  sink(header.data(), header.size());
  std::vector<unsigned char> chunk;
  const std::size_t record = colors.empty() ? 16 : 19;
  chunk.reserve(std::min(kBufferBytes, record * spheres.count));
  for (std::size_t i = 0; i < spheres.count; ++i) {
    for (float v : {spheres.cx[i], spheres.cy[i], spheres.cz[i], spheres.radius[i]}) {
      const auto bits = std::bit_cast<std::uint32_t>(v);
      for (int k = 0; k < 32; k += 8)
        chunk.push_back(static_cast<unsigned char>(bits >> k & 0xff));
    }
    if (!colors.empty()) {
      for (float c : {colors[i].x, colors[i].y, colors[i].z}) {
        // Rounded, so that k / 255 reads back as written; NaN as 0.
        const float unit = c > 0.0f ? std::min(c, 1.0f) : 0.0f;
        chunk.push_back(static_cast<unsigned char>(std::lround(unit * 255.0f)));
      }
    }
    if (chunk.size() + record > kBufferBytes || i + 1 == spheres.count) {  // the next would not fit
      sink(chunk.data(), chunk.size());
      chunk.clear();
    }
  }
}

}  // namespace sphray::particles
