// `sphray convert IN OUT`: the spheres of any scene the command reads (a preset, a JSON scene,
// a particle file) written as a particle file, its format chosen by OUT's extension.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

namespace sphray::render::convert {

struct ConvertArgs {
  std::string input;
  std::string output;
  std::optional<float> radius;  // the radius of a particle file's particles, if it has none
  bool quiet = false;
  bool force = false;  // replace a read-only output
};

/// Registers convert's arguments and options on its subcommand.
void add_convert_options(CLI::App& convert, ConvertArgs& args);

/// Runs the conversion: 0, or 2 for a refusal (bad input, an output that may not be written,
/// an unknown extension), 1 for a failure while writing; every failure one line on stderr and
/// an existing output untouched.
int run_convert(const ConvertArgs& args);

}  // namespace sphray::render::convert
