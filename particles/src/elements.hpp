// The chemical elements as the PDB reader needs them: a symbol's van der Waals radius and CPK
// colour (elements.cpp holds the table and its sources).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace sphray::particles::detail {

struct Element {
  std::string_view symbol;  // as the periodic table writes it: "C", "Fe"
  float radius;             // van der Waals radius, angstroms
  std::uint32_t rgb;        // CPK colour, 0xRRGGBB
};

/// The element whose symbol is symbol, in any case ("FE", "fe", "Fe"); nothing for a symbol
/// that names no element.
std::optional<Element> find_element(std::string_view symbol);

}  // namespace sphray::particles::detail
