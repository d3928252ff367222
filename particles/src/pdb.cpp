// PDB atoms (.pdb, .ent): the ATOM and HETATM records of the first model, in the fixed columns
// of the PDB format v3.3 (wwPDB, "Atomic Coordinate Entry Format Description", section 9), one
// sphere per atom: its element's van der Waals radius and CPK colour (elements.cpp). A line at
// a time, through the text readers' buffer; every refusal one line, "FILE:LINE: expected ...".
#include <cmath>

#include "elements.hpp"
#include "sphray/particles/particles.hpp"
#include "text_lines.hpp"

namespace sphray::particles {
namespace {

using detail::Element;
using detail::find_element;
using detail::quoted;

// Columns 1-based and inclusive, as the format's tables give them.
struct Columns {
  std::size_t first, last;
  const char* name;
};
constexpr Columns kXColumns{31, 38, "x"}, kYColumns{39, 46, "y"}, kZColumns{47, 54, "z"};
constexpr Columns kNameColumns{13, 16, "atom name"}, kElementColumns{77, 78, "element"};

// A record's columns, shorter (or empty) where the line ends before them.
std::string_view field(std::string_view line, Columns c) {
  if (line.size() < c.first) return {};
  return line.substr(c.first - 1, c.last - c.first + 1);
}

bool digit_or_blank(char c) {
  return c == ' ' || (c >= '0' && c <= '9');
}

// ATOM and HETATM are the records with coordinates. "ATOM" is followed by two blanks, or by the
// serial's leading digits in files of 100,000 atoms or more whose writers let it overflow
// leftwards (VMD's and others' PDB readers take those too).
bool is_atom_record(std::string_view line) {
  if (line.starts_with("HETATM")) return true;
  if (!line.starts_with("ATOM")) return false;
  for (std::size_t i = 4; i < 6 && i < line.size(); ++i) {
    if (!digit_or_blank(line[i])) return false;
  }
  return true;
}

// The element of an atom whose element columns (77-78) are blank, from its name (columns
// 13-16), as common readers guess it (Biopython's PDBParser, VMD's guess from the name). The
// format right-justifies the element symbol in columns 13-14 of the name: "Alignment of
// one-letter atom name such as C starts at column 14, while two-letter atom name such as FE
// starts at column 13" (v3.3, ATOM). So:
//   - column 13 blank or a digit: the letter of column 14 (" CA " an alpha carbon, "1HB " a
//     hydrogen);
//   - an 'H' in column 13 followed by two characters or more: hydrogen ("HG21", "HD11", and
//     the left-justified "HE2 " of some writers), not mercury or helium, which the convention
//     names "HG  " and "HE  ";
//   - otherwise columns 13-14 when they are an element symbol ("FE  " iron, "CA  " calcium,
//     "CL1 " chlorine), else column 13 alone ("C1A " carbon).
std::optional<Element> element_from_name(std::string_view name) {
  if (name.size() < 2) return std::nullopt;
  if (digit_or_blank(name[0])) return find_element(name.substr(1, 1));
  if ((name[0] == 'H' || name[0] == 'h') && detail::trim(name).size() > 2) return find_element("H");
  if (const auto two = find_element(name.substr(0, 2))) return two;
  return find_element(name.substr(0, 1));
}

// The parser: fed one line at a time (without its '\n'), in order, until it says to stop.
class PdbParser {
 public:
  explicit PdbParser(std::string source) : source_(std::move(source)) {}

  // False at the end of the first model: the records after it are other models' atoms.
  bool line(std::string_view text, std::uint64_t number) {
    line_ = number;
    if (text.starts_with("ENDMDL")) return false;
    if (text.ends_with('\r')) text.remove_suffix(1);  // CRLF line ends
    if (is_atom_record(text)) atom(text);
    return true;
  }

  Points finish() {
    if (points_.spheres.size() == 0)
      throw ParticleError(source_ + ": expected ATOM or HETATM records, the file has none");
    return std::move(points_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw ParticleError(source_ + ":" + std::to_string(line_) + ": expected " + what);
  }

  static std::string columns(Columns c) {
    return "columns " + std::to_string(c.first) + "-" + std::to_string(c.last) + " (" + c.name +
           ")";
  }

  float coordinate(std::string_view text, Columns c) const {
    const std::string_view raw = field(text, c);
    const std::string_view value_text = detail::trim(raw);
    bool range = false;
    const std::optional<float> value = detail::as_number(value_text, range);
    if (range) fail(columns(c) + " within float's range, got " + quoted(raw));
    if (!value) fail(columns(c) + " to be a number, got " + quoted(raw));
    if (!std::isfinite(*value)) fail(columns(c) + " to be finite, got " + quoted(raw));
    if (std::abs(*value) > detail::kMaxMagnitude)
      fail(columns(c) + " at most 1e17 in magnitude, got " + quoted(raw));
    return *value;
  }

  Element element(std::string_view text) const {
    const std::string_view symbol = detail::trim(field(text, kElementColumns));
    if (!symbol.empty()) {
      if (const auto e = find_element(symbol)) return *e;
      fail("an element symbol in " + columns(kElementColumns) + ", got " + quoted(symbol));
    }
    const std::string_view name = field(text, kNameColumns);
    if (const auto e = element_from_name(name)) return *e;
    fail("an element symbol in " + columns(kElementColumns) + " or at the start of " +
         columns(kNameColumns) + ", got " + quoted(name));
  }

  void atom(std::string_view text) {
    if (points_.spheres.size() >= kMaxParticles) fail("at most 2^32 - 2 atoms");
    const Vec3 center{coordinate(text, kXColumns), coordinate(text, kYColumns),
                      coordinate(text, kZColumns)};
    const Element e = element(text);
    points_.spheres.add(center, e.radius);
    points_.colors.push_back({static_cast<float>(e.rgb >> 16) / 255.0f,
                              static_cast<float>((e.rgb >> 8) & 0xFF) / 255.0f,
                              static_cast<float>(e.rgb & 0xFF) / 255.0f});
  }

  std::string source_;
  std::uint64_t line_ = 0;
  Points points_;
};

}  // namespace

Points parse_pdb(std::string_view text, const std::string& source) {
  PdbParser parser(source);
  detail::split_lines(text, source,
                      [&](std::string_view line, std::uint64_t n) { return parser.line(line, n); });
  return parser.finish();
}

Points read_pdb(const std::filesystem::path& file) {
  PdbParser parser(file.string());
  detail::read_lines(file,
                     [&](std::string_view line, std::uint64_t n) { return parser.line(line, n); });
  return parser.finish();
}

}  // namespace sphray::particles
