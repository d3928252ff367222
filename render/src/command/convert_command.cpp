#include "command/convert_command.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <new>

#include "command/command_failure.hpp"
#include "command/progress_report.hpp"
#include "image/atomic_output.hpp"
#include "sphray/particles/particles.hpp"
#include "sphray/render/image_file.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render::convert {

void add_convert_options(CLI::App& convert, ConvertArgs& args) {
  convert
      .add_option("IN", args.input,
                  "A preset (see `sphray scenes`), a .json file or a particle file (.sphp, .xyz, "
                  ".csv)")
      ->required();
  convert.add_option("OUT", args.output, "The particle file to write: .sphp, .xyz, .csv or .ply")
      ->required();
  convert
      .add_option("--radius", args.radius,
                  "The radius of every particle of a .xyz or .csv file without a radius column")
      ->check(CLI::Range(0x1p-126, 1e17))
      ->type_name("R");
  convert.add_flag("--quiet,-q", args.quiet, "No progress line, no summary line");
  convert.add_flag("--force,-f", args.force, "Replace the output even if it is read-only");
}

int run_convert(const ConvertArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  try {
    // Refused before anything is read: an extension no writer has, an output that may not be
    // replaced (the temporary is made now; OUT itself is only ever replaced whole).
    particles::check_particle_output(args.output);
    detail::AtomicOutput output(args.output, args.force);
    progress::Reporter reporter(!args.quiet, ::isatty(STDERR_FILENO) == 1);
    reporter.phase("reading " + args.input);
    // A particle file's colours only when it has them: an empty Scene::colors is grey.
    const Scene input = load_scene_or_preset(args.input, {args.radius, {}});
    reporter.phase("writing " + args.output);
    std::uint64_t bytes = 0;
    particles::write_particle_file(
        [&](const void* data, std::size_t size) {
          output.write(data, size);
          bytes += size;
        },
        args.output, input.spheres.view(), input.colors);
    output.commit();
    reporter.finish();
    const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;
    if (!args.quiet) {
      std::printf("wrote %s: %zu particles, %llu bytes, %.3f s\n", args.output.c_str(),
                  input.spheres.size(), static_cast<unsigned long long>(bytes), seconds.count());
    }
    return 0;
  } catch (...) {
    return report_failure(args.input + ": out of memory while converting");
  }
}

}  // namespace sphray::render::convert
