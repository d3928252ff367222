// Text points (.xyz, .csv): a line at a time, through a fixed buffer, into the SoA; every
// refusal one line, "FILE:LINE: expected ..., got ...".
#include <algorithm>
#include <array>
#include <cmath>

#include "sphray/particles/particles.hpp"
#include "support.hpp"
#include "text_lines.hpp"

namespace sphray::particles {
namespace {

using detail::as_number;
using detail::kMaxMagnitude;
using detail::lower;
using detail::quoted;
using detail::shortest;
using detail::trim;

// The columns a file may have, in the order a file without a header gives them.
enum Column { kX, kY, kZ, kRadius, kRed, kGreen, kBlue, kColumns };
constexpr std::array<std::string_view, kColumns> kColumnNames = {"x",   "y",     "z",   "radius",
                                                                 "red", "green", "blue"};
constexpr int kAbsent = -1;

// The parser: fed one line at a time (without its '\n'), in order.
class PointParser {
 public:
  PointParser(std::string source, const PointOptions& options)
      : source_(std::move(source)), options_(options) {
    detail::check_radius_option(source_, options);
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
    // Colours are checked for finiteness here and for their range below.
    const char* problem = detail::coordinate_problem(*value, column == kRadius);
    if (problem != nullptr && (column <= kRadius || !std::isfinite(*value)))
      fail(name() + " " + problem + ", got " + quoted(fields_[i]));
    if (column >= kRed && !(*value >= 0 && *value <= 255))
      fail(name() + " in [0, 1] or [0, 255], got " + quoted(fields_[i]));
    return *value;
  }

  // The same field as a double, once number() has accepted it: the digits as written.
  double exact(Column column) const {
    bool range = false;
    return *detail::as_double(fields_[static_cast<std::size_t>(columns_[column])], range);
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
    if (options_.keep_doubles) {
      const double exact_radius = columns_[kRadius] != kAbsent ? exact(kRadius) : radius;
      points_.doubles.add(Vec3d{exact(kX), exact(kY), exact(kZ)}, exact_radius);
    }
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

}  // namespace

Points parse_points(std::string_view text, const std::string& source, const PointOptions& options) {
  PointParser parser(source, options);
  detail::split_lines(text, source, [&](std::string_view line, std::uint64_t) {
    parser.line(line);
    return true;
  });
  return parser.finish();
}

Points read_points(const std::filesystem::path& file, const PointOptions& options) {
  PointParser parser(file.string(), options);
  detail::read_lines(file, [&](std::string_view line, std::uint64_t) {
    parser.line(line);
    return true;
  });
  return parser.finish();
}

bool is_particle_file(const std::filesystem::path& path) {
  const std::string ext = lower(path.extension().string());
  return ext == ".sphp" || ext == ".xyz" || ext == ".csv" || ext == ".ply" || ext == ".pdb" ||
         ext == ".ent";
}

Points read_particle_file(const std::filesystem::path& path, const PointOptions& options) {
  const std::string ext = lower(path.extension().string());
  if (SphpFile::named(path)) return {read_sphp(path), {}, {}};
  if (ext == ".xyz" || ext == ".csv") return read_points(path, options);
  if (ext == ".ply") return read_ply(path, options);
  if (ext == ".pdb" || ext == ".ent") return read_pdb(path);
  throw ParticleError(path.string() +
                      ": expected a particle file ending in .sphp, .xyz, .csv, .ply, .pdb or .ent");
}

}  // namespace sphray::particles
