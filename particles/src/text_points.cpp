// Text points (.xyz, .csv): a line at a time, through a fixed buffer, into the SoA; every
// refusal one line, "FILE:LINE: expected ..., got ...".
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>

#include "sphray/particles/particles.hpp"

namespace sphray::particles {
namespace {

// The columns a file may have, in the order a file without a header gives them.
enum Column { kX, kY, kZ, kRadius, kRed, kGreen, kBlue, kColumns };
constexpr std::array<std::string_view, kColumns> kColumnNames = {"x",   "y",     "z",   "radius",
                                                                 "red", "green", "blue"};
constexpr int kAbsent = -1;

// Coordinates and radii at most this in magnitude: their squares (and the kernel's products of
// them) stay far inside float's range, as for scene files.
constexpr float kMaxMagnitude = 1e17f;

// A field quoted for a message: at most 40 bytes, bytes outside printable ASCII as \xHH, so that
// the message stays one line whatever the file holds.
std::string quoted(std::string_view field) {
  std::string out = "\"";
  for (std::size_t i = 0; i < field.size() && i < 40; ++i) {
    const auto c = static_cast<unsigned char>(field[i]);
    if (c >= 0x20 && c < 0x7f && c != '"' && c != '\\') {
      out += static_cast<char>(c);
    } else {
      constexpr char kHex[] = "0123456789abcdef";
      out += {'\\', 'x', kHex[c >> 4], kHex[c & 15]};
    }
  }
  return out + (field.size() > 40 ? "...\"" : "\"");
}

std::string lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c + 32) : c; });
  return out;
}

std::string shortest(float value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

std::string_view trim(std::string_view s) {
  const auto blank = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
  };
  while (!s.empty() && blank(s.front()))
    s.remove_prefix(1);
  while (!s.empty() && blank(s.back()))
    s.remove_suffix(1);
  return s;
}

std::optional<float> as_number(std::string_view field, bool& out_of_range) {
  out_of_range = false;
  // A leading '+' (printf's %+g) is a sign; from_chars takes only '-'.
  if (field.starts_with('+')) {
    field.remove_prefix(1);
    if (field.starts_with('+') || field.starts_with('-')) return std::nullopt;  // "+-1"
  }
  float value = 0;
  const char* end = field.data() + field.size();
  const auto [stop, error] = std::from_chars(field.data(), end, value);
  out_of_range = error == std::errc::result_out_of_range && stop == end;
  if (error != std::errc{} || stop != end) return std::nullopt;
  return value;
}

// The parser: fed one line at a time (without its '\n'), in order.
class PointParser {
 public:
  PointParser(std::string source, const PointOptions& options)
      : source_(std::move(source)), options_(options) {
    if (options.radius && !(std::isfinite(*options.radius) && *options.radius > 0 &&
                            *options.radius <= kMaxMagnitude)) {
      throw ParticleError(source_ +
                          ": expected the radius given for the file to be positive and "
                          "at most 1e17, got " +
                          shortest(*options.radius));
    }
  }

  void line(std::string_view text) {
    ++line_;
    if (line_ == 1 && text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // a BOM
    if (const std::size_t hash = text.find('#'); hash != std::string_view::npos)
      text = text.substr(0, hash);
    text = trim(text);
    if (text.empty()) return;
    if (!started_) {
      started_ = true;
      comma_ = text.find(',') != std::string_view::npos;
      split(text);
      bool range = false;
      if (!as_number(fields_[0], range) && !range) {
        header();
        return;
      }
      by_count();
    } else {
      split(text);
    }
    point();
  }

  Points finish() {
    if (points_.spheres.size() == 0)
      throw ParticleError(source_ + ": expected particles, the file has none");
    if (columns_[kRed] != kAbsent && max_color_ > 1.0f) {  // 0-255 colours
      for (Vec3& c : points_.colors)
        c = {c.x / 255.0f, c.y / 255.0f, c.z / 255.0f};  // 51 is 0.2f exactly
    }
    return std::move(points_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw ParticleError(source_ + ":" + std::to_string(line_) + ": expected " + what);
  }

  void split(std::string_view text) {
    fields_.clear();
    if (comma_) {
      for (;;) {
        const std::size_t comma = text.find(',');
        fields_.push_back(trim(text.substr(0, comma)));
        if (comma == std::string_view::npos) break;
        text.remove_prefix(comma + 1);
      }
      return;
    }
    while (!text.empty()) {
      const std::size_t end = text.find_first_of(" \t\r\v\f");
      fields_.push_back(text.substr(0, end));
      text = trim(text.substr(std::min(end, text.size())));
    }
  }

  // A header line: each field names a column.
  void header() {
    columns_.fill(kAbsent);
    for (std::size_t i = 0; i < fields_.size(); ++i) {
      std::string name = lower(fields_[i]);
      if (name == "r") name = "radius";
      const auto* known = std::find(kColumnNames.begin(), kColumnNames.end(), name);
      if (known == kColumnNames.end()) {
        fail("column names x, y, z, radius (or r), red, green, blue, got " + quoted(fields_[i]));
      }
      int& column = columns_[static_cast<std::size_t>(known - kColumnNames.begin())];
      if (column != kAbsent) fail("each column named once, got " + quoted(fields_[i]) + " twice");
      column = static_cast<int>(i);
    }
    if (columns_[kX] == kAbsent || columns_[kY] == kAbsent || columns_[kZ] == kAbsent)
      fail("columns named x, y and z in the header");
    const int colours =
        (columns_[kRed] != kAbsent) + (columns_[kGreen] != kAbsent) + (columns_[kBlue] != kAbsent);
    if (colours != 0 && colours != 3) fail("red, green and blue columns together, or none");
    width_ = fields_.size();
    check_radius();
  }

  // No header: the number of columns says which they are.
  void by_count() {
    columns_.fill(kAbsent);
    width_ = fields_.size();
    if (width_ != 3 && width_ != 4 && width_ != 6 && width_ != 7) {
      fail("3, 4, 6 or 7 columns (x y z [radius] [red green blue]) or a header naming them, got " +
           std::to_string(width_));
    }
    int next = 0;
    for (Column c : {kX, kY, kZ})
      columns_[c] = next++;
    if (width_ == 4 || width_ == 7) columns_[kRadius] = next++;
    if (width_ >= 6) {
      for (Column c : {kRed, kGreen, kBlue})
        columns_[c] = next++;
    }
    check_radius();
  }

  void check_radius() const {
    if (columns_[kRadius] == kAbsent && !options_.radius)
      fail("a radius column, or a radius given for the file (sphray render --radius R)");
  }

  float number(Column column) const {
    const std::size_t i = static_cast<std::size_t>(columns_[column]);
    // The column's name for a message, made only when one is: this runs for every field.
    const auto name = [&] {
      return "column " + std::to_string(i + 1) + " (" + std::string(kColumnNames[column]) + ")";
    };
    bool range = false;
    const std::optional<float> value = as_number(fields_[i], range);
    if (range) fail(name() + " within float's range, got " + quoted(fields_[i]));
    if (!value) fail(name() + " to be a number, got " + quoted(fields_[i]));
    if (!std::isfinite(*value)) fail(name() + " to be finite, got " + quoted(fields_[i]));
    if (column == kRadius && !(*value > 0))
      fail(name() + " to be positive, got " + quoted(fields_[i]));
    if (column <= kRadius && std::abs(*value) > kMaxMagnitude)
      fail(name() + " at most 1e17 in magnitude, got " + quoted(fields_[i]));
    if (column >= kRed && !(*value >= 0 && *value <= 255))
      fail(name() + " in [0, 1] or [0, 255], got " + quoted(fields_[i]));
    return *value;
  }

  void point() {
    if (fields_.size() != width_) {
      fail(std::to_string(width_) + " columns, as the first line has, got " +
           std::to_string(fields_.size()));
    }
    if (points_.spheres.size() >= kMaxParticles) fail("at most 2^32 - 2 particles");
    const Vec3 center{number(kX), number(kY), number(kZ)};
    const float radius = columns_[kRadius] != kAbsent ? number(kRadius) : *options_.radius;
    if (columns_[kRed] != kAbsent) {
      const Vec3 color{number(kRed), number(kGreen), number(kBlue)};
      max_color_ = std::max({max_color_, color.x, color.y, color.z});
      points_.colors.push_back(color);
    }
    points_.spheres.add(center, radius);
  }

  std::string source_;
  PointOptions options_;
  std::uint64_t line_ = 0;
  bool started_ = false;
  bool comma_ = false;
  std::size_t width_ = 0;
  std::array<int, kColumns> columns_{};
  std::vector<std::string_view> fields_;
  float max_color_ = 0;
  Points points_;
};

// Closes the file when the reading ends, however it ends.
struct Closing {
  int fd;
  ~Closing() {
    if (fd >= 0) ::close(fd);
  }
};

[[noreturn]] void refuse_errno(const std::string& source, int error) {
  throw ParticleError(source + ": cannot read the particle file (" + std::strerror(error) + ")");
}

}  // namespace

Points parse_points(std::string_view text, const std::string& source, const PointOptions& options) {
  PointParser parser(source, options);
  std::uint64_t line = 0;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    ++line;
    if (std::min(end, text.size()) > kMaxLineBytes) {
      throw ParticleError(source + ":" + std::to_string(line) + ": expected lines of at most " +
                          std::to_string(kMaxLineBytes) + " bytes");
    }
    parser.line(text.substr(0, end));
    text.remove_prefix(std::min(end, text.size() - 1) + 1);
  }
  return parser.finish();
}

Points read_points(const std::filesystem::path& file, const PointOptions& options) {
  const std::string source = file.string();
  // O_NONBLOCK: opening a FIFO would otherwise wait for a writer; only regular files are read.
  Closing fd{::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK)};
  if (fd.fd < 0) refuse_errno(source, errno);
  struct stat st {};
  if (::fstat(fd.fd, &st) != 0) refuse_errno(source, errno);
  if (S_ISDIR(st.st_mode))
    throw ParticleError(source + ": expected a particle file, got a directory");
  if (!S_ISREG(st.st_mode)) throw ParticleError(source + ": expected a regular file");
  PointParser parser(source, options);
  // One buffer: a line that straddles two reads is moved to its front before the next read.
  std::vector<char> buffer(std::size_t{1} << 16);
  std::size_t held = 0;  // bytes of an unfinished line at the front of buffer
  std::uint64_t line = 0;
  for (;;) {
    const ssize_t n = ::read(fd.fd, buffer.data() + held, buffer.size() - held);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) refuse_errno(source, errno);
    const std::size_t filled = held + static_cast<std::size_t>(n);
    std::string_view text(buffer.data(), filled);
    std::size_t end;
    while ((end = text.find('\n')) != std::string_view::npos) {
      ++line;
      if (end > kMaxLineBytes) break;
      parser.line(text.substr(0, end));
      text.remove_prefix(end + 1);
    }
    if (text.size() > kMaxLineBytes || (end != std::string_view::npos)) {
      throw ParticleError(source + ":" + std::to_string(line + (end == std::string_view::npos)) +
                          ": expected lines of at most " + std::to_string(kMaxLineBytes) +
                          " bytes");
    }
    if (n == 0) {
      if (!text.empty()) parser.line(text);  // the last line, without its '\n'
      return parser.finish();
    }
    std::memmove(buffer.data(), text.data(), text.size());
    held = text.size();
  }
}

bool SphpFile::named(const std::filesystem::path& path) {
  return lower(path.extension().string()) == ".sphp";
}

bool is_particle_file(const std::filesystem::path& path) {
  const std::string ext = lower(path.extension().string());
  return ext == ".sphp" || ext == ".xyz" || ext == ".csv";
}

Points read_particle_file(const std::filesystem::path& path, const PointOptions& options) {
  const std::string ext = lower(path.extension().string());
  if (SphpFile::named(path)) return {read_sphp(path), {}};
  if (ext == ".xyz" || ext == ".csv") return read_points(path, options);
  throw ParticleError(path.string() + ": expected a particle file ending in .sphp, .xyz or .csv");
}

}  // namespace sphray::particles
