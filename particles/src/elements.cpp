// The element table of the PDB reader: van der Waals radii and CPK colours, elements 1-109 (the
// ones Jmol colours) and deuterium.
//
// Radii, angstroms:
//   - A. Bondi, "van der Waals Volumes and Radii", J. Phys. Chem. 68, 441-451 (1964), for the
//     38 elements he gave (H 1.20, C 1.70, N 1.55, O 1.52, P 1.80, S 1.80, ...);
//   - M. Mantina, A. C. Chamberlin, R. Valero, C. J. Cramer, D. G. Truhlar, "Consistent van der
//     Waals Radii for the Whole Main Group", J. Phys. Chem. A 113, 5806-5812 (2009), table 12,
//     for the main-group elements Bondi lacks (Be, B, Al, Ca, Ge, Rb, Sr, Sb, Cs, Ba, Bi, Po,
//     At, Rn, Fr, Ra). Bondi's values plus these are the table most tools print (ASE, the
//     Wikipedia table); Mantina's H (1.10, from Rowland and Taylor) is not used, Bondi's 1.20 is.
//   - kNoRadius for every other element (most transition metals, the lanthanides and
//     actinides but U): no measured value in either source. find_element() gives them 2.00,
//     the value the Cambridge Structural Database and VMD (PeriodicTable.C) use for an element
//     without a Bondi radius (docs/decisions.md, "PDB atoms").
// Colours: Jmol's CPK colours (jmol.sourceforge.net/jscolors, "Jmol colors"), as 0xRRGGBB;
// deuterium is Jmol's 0xFFFFC0 with hydrogen's radius.
#include "elements.hpp"

#include <array>

namespace sphray::particles::detail {
namespace {

constexpr float kNoRadius = 0;
constexpr float kDefaultRadius = 2.00f;

constexpr std::array<Element, 110> kElements = {{
    {"H", 1.20f, 0xFFFFFF},      {"He", 1.40f, 0xD9FFFF},     {"Li", 1.82f, 0xCC80FF},
    {"Be", 1.53f, 0xC2FF00},     {"B", 1.92f, 0xFFB5B5},      {"C", 1.70f, 0x909090},
    {"N", 1.55f, 0x3050F8},      {"O", 1.52f, 0xFF0D0D},      {"F", 1.47f, 0x90E050},
    {"Ne", 1.54f, 0xB3E3F5},     {"Na", 2.27f, 0xAB5CF2},     {"Mg", 1.73f, 0x8AFF00},
    {"Al", 1.84f, 0xBFA6A6},     {"Si", 2.10f, 0xF0C8A0},     {"P", 1.80f, 0xFF8000},
    {"S", 1.80f, 0xFFFF30},      {"Cl", 1.75f, 0x1FF01F},     {"Ar", 1.88f, 0x80D1E3},
    {"K", 2.75f, 0x8F40D4},      {"Ca", 2.31f, 0x3DFF00},     {"Sc", kNoRadius, 0xE6E6E6},
    {"Ti", kNoRadius, 0xBFC2C7}, {"V", kNoRadius, 0xA6A6AB},  {"Cr", kNoRadius, 0x8A99C7},
    {"Mn", kNoRadius, 0x9C7AC7}, {"Fe", kNoRadius, 0xE06633}, {"Co", kNoRadius, 0xF090A0},
    {"Ni", 1.63f, 0x50D050},     {"Cu", 1.40f, 0xC88033},     {"Zn", 1.39f, 0x7D80B0},
    {"Ga", 1.87f, 0xC28F8F},     {"Ge", 2.11f, 0x668F8F},     {"As", 1.85f, 0xBD80E3},
    {"Se", 1.90f, 0xFFA100},     {"Br", 1.85f, 0xA62929},     {"Kr", 2.02f, 0x5CB8D1},
    {"Rb", 3.03f, 0x702EB0},     {"Sr", 2.49f, 0x00FF00},     {"Y", kNoRadius, 0x94FFFF},
    {"Zr", kNoRadius, 0x94E0E0}, {"Nb", kNoRadius, 0x73C2C9}, {"Mo", kNoRadius, 0x54B5B5},
    {"Tc", kNoRadius, 0x3B9E9E}, {"Ru", kNoRadius, 0x248F8F}, {"Rh", kNoRadius, 0x0A7D8C},
    {"Pd", 1.63f, 0x006985},     {"Ag", 1.72f, 0xC0C0C0},     {"Cd", 1.58f, 0xFFD98F},
    {"In", 1.93f, 0xA67573},     {"Sn", 2.17f, 0x668080},     {"Sb", 2.06f, 0x9E63B5},
    {"Te", 2.06f, 0xD47A00},     {"I", 1.98f, 0x940094},      {"Xe", 2.16f, 0x429EB0},
    {"Cs", 3.43f, 0x57178F},     {"Ba", 2.68f, 0x00C900},     {"La", kNoRadius, 0x70D4FF},
    {"Ce", kNoRadius, 0xFFFFC7}, {"Pr", kNoRadius, 0xD9FFC7}, {"Nd", kNoRadius, 0xC7FFC7},
    {"Pm", kNoRadius, 0xA3FFC7}, {"Sm", kNoRadius, 0x8FFFC7}, {"Eu", kNoRadius, 0x61FFC7},
    {"Gd", kNoRadius, 0x45FFC7}, {"Tb", kNoRadius, 0x30FFC7}, {"Dy", kNoRadius, 0x1FFFC7},
    {"Ho", kNoRadius, 0x00FF9C}, {"Er", kNoRadius, 0x00E675}, {"Tm", kNoRadius, 0x00D452},
    {"Yb", kNoRadius, 0x00BF38}, {"Lu", kNoRadius, 0x00AB24}, {"Hf", kNoRadius, 0x4DC2FF},
    {"Ta", kNoRadius, 0x4DA6FF}, {"W", kNoRadius, 0x2194D6},  {"Re", kNoRadius, 0x267DAB},
    {"Os", kNoRadius, 0x266696}, {"Ir", kNoRadius, 0x175487}, {"Pt", 1.75f, 0xD0D0E0},
    {"Au", 1.66f, 0xFFD123},     {"Hg", 1.55f, 0xB8B8D0},     {"Tl", 1.96f, 0xA6544D},
    {"Pb", 2.02f, 0x575961},     {"Bi", 2.07f, 0x9E4FB5},     {"Po", 1.97f, 0xAB5C00},
    {"At", 2.02f, 0x754F45},     {"Rn", 2.20f, 0x428296},     {"Fr", 3.48f, 0x420066},
    {"Ra", 2.83f, 0x007D00},     {"Ac", kNoRadius, 0x70ABFA}, {"Th", kNoRadius, 0x00BAFF},
    {"Pa", kNoRadius, 0x00A1FF}, {"U", 1.86f, 0x008FFF},      {"Np", kNoRadius, 0x0080FF},
    {"Pu", kNoRadius, 0x006BFF}, {"Am", kNoRadius, 0x545CF2}, {"Cm", kNoRadius, 0x785CE3},
    {"Bk", kNoRadius, 0x8A4FE3}, {"Cf", kNoRadius, 0xA136D4}, {"Es", kNoRadius, 0xB31FD4},
    {"Fm", kNoRadius, 0xB31FBA}, {"Md", kNoRadius, 0xB30DA6}, {"No", kNoRadius, 0xBD0D87},
    {"Lr", kNoRadius, 0xC70066}, {"Rf", kNoRadius, 0xCC0059}, {"Db", kNoRadius, 0xD1004F},
    {"Sg", kNoRadius, 0xD90045}, {"Bh", kNoRadius, 0xE00038}, {"Hs", kNoRadius, 0xE6002E},
    {"Mt", kNoRadius, 0xEB0026}, {"D", 1.20f, 0xFFFFC0},
}};

char upper(char c) {
  return c >= 'a' && c <= 'z' ? static_cast<char>(c - 32) : c;
}

bool same_symbol(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (upper(a[i]) != upper(b[i])) return false;
  }
  return true;
}

}  // namespace

std::optional<Element> find_element(std::string_view symbol) {
  for (Element e : kElements) {  // 110 entries, a few per atom: no index needed
    if (same_symbol(e.symbol, symbol)) {
      if (e.radius == kNoRadius) e.radius = kDefaultRadius;
      return e;
    }
  }
  return std::nullopt;
}

}  // namespace sphray::particles::detail
