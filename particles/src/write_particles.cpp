// Writing particle files: text points (.xyz, .csv) and the choice of a writer by extension.
// Floats are written by std::to_chars without a precision, the shortest text that reads back
// to the same float: a file written here and read by read_points gives the same bits.
#include <algorithm>
#include <charconv>
#include <stdexcept>

#include "sphray/particles/particles.hpp"

namespace sphray::particles {
namespace {

// Lines are gathered up to this many bytes before going to the sink.
constexpr std::size_t kChunkBytes = std::size_t{1} << 20;
// The longest line: seven floats of at most 15 characters each ("-1.17549435e-38") and their
// separators, with room to spare.
constexpr std::size_t kLineBytes = 7 * 16 + 8;

std::string extension_of(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c + 32) : c; });
  return ext;
}

// Appends the fields of one line, separated, and its '\n'.
char* put_line(char* out, std::initializer_list<float> fields, char separator) {
  bool first = true;
  for (float v : fields) {
    if (!first) *out++ = separator;
    first = false;
    out = std::to_chars(out, out + 16, v).ptr;
  }
  *out++ = '\n';
  return out;
}

std::string header_line(bool colors, char separator) {
  std::string line;
  for (const char* name : {"x", "y", "z", "radius", "red", "green", "blue"}) {
    if (!colors && name[0] == 'r' && name[1] == 'e') break;  // "red": the colour columns
    if (!line.empty()) line += separator;
    line += name;
  }
  return line + '\n';
}

}  // namespace

void write_points(const ByteSink& sink, SphereView spheres, std::span<const Vec3> colors,
                  char separator) {
  check_particle_count(spheres.count);
  if (!colors.empty() && colors.size() != spheres.count)
    throw std::invalid_argument("write_points: expected one colour per sphere, or none");
  const std::string header = header_line(!colors.empty(), separator);
  sink(header.data(), header.size());
  std::vector<char> chunk(kChunkBytes + kLineBytes);
  char* end = chunk.data();
  for (std::size_t i = 0; i < spheres.count; ++i) {
    end = colors.empty()
              ? put_line(end, {spheres.cx[i], spheres.cy[i], spheres.cz[i], spheres.radius[i]},
                         separator)
              : put_line(end,
                         {spheres.cx[i], spheres.cy[i], spheres.cz[i], spheres.radius[i],
                          colors[i].x, colors[i].y, colors[i].z},
                         separator);
    if (static_cast<std::size_t>(end - chunk.data()) >= kChunkBytes) {
      sink(chunk.data(), static_cast<std::size_t>(end - chunk.data()));
      end = chunk.data();
    }
  }
  if (end != chunk.data()) sink(chunk.data(), static_cast<std::size_t>(end - chunk.data()));
}

void check_particle_output(const std::filesystem::path& path) {
  const std::string ext = extension_of(path);
  if (ext == ".sphp" || ext == ".xyz" || ext == ".csv" || ext == ".ply") return;
  throw ParticleError(path.string() +
                      ": expected an output particle file ending in .sphp, .xyz, .csv or .ply");
}

void write_particle_file(const ByteSink& sink, const std::filesystem::path& path,
                         SphereView spheres, std::span<const Vec3> colors) {
  check_particle_output(path);
  const std::string ext = extension_of(path);
  if (ext == ".sphp") return write_sphp(sink, spheres);
  if (ext == ".ply") return write_ply(sink, spheres, colors);
  write_points(sink, spheres, colors, ext == ".csv" ? ',' : ' ');
}

}  // namespace sphray::particles
