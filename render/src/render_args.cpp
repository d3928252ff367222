#include "render_args.hpp"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <limits>

#include "sphray/render/image_file.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {

CLI::Validator seed_range() {
  const std::string range = "0 to " + std::to_string(std::numeric_limits<std::uint64_t>::max());
  return CLI::Validator(
      [range](std::string& text) -> std::string {
        std::uint64_t value = 0;
        const char* end = text.data() + text.size();
        auto [stop, error] = std::from_chars(text.data(), end, value);
        const bool digits_only = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
          return c >= '0' && c <= '9';
        });
        if (digits_only && error == std::errc() && stop == end) return "";
        return "Value " + text + " not in range " + range;
      },
      "UINT64", "seed range");
}

CLI::Validator seconds_validator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double seconds = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !(seconds >= 0.0 && seconds <= 1e9))
          return "expected seconds from 0 to 1e9, got " + text;
        return {};
      },
      "SECONDS");
}

void add_render_options(CLI::App& render, RenderArgs& args, RenderArgsScope scope) {
  render
      .add_option("--scene,-s", args.scene,
                  "A preset (see `sphray scenes`), a .json file or a particle file (.sphp, .xyz, "
                  ".csv)")
      ->capture_default_str();
  render
      .add_option("--radius", args.radius,
                  "The radius of every particle of a .xyz or .csv file without a radius column")
      ->check(CLI::Range(0x1p-126, 1e17))
      ->type_name("R");
  render.add_option("--mode,-m", args.mode, "What to show")
      ->check(CLI::IsMember(mode_names()))
      ->capture_default_str();
  render.add_option("--width,-W", args.width, "Image width (default: the scene's)")
      ->check(CLI::Range(1, kMaxImageSide));
  render.add_option("--height,-H", args.height, "Image height (default: the scene's)")
      ->check(CLI::Range(1, kMaxImageSide));
  render.add_option("--spp", args.spp, "Samples per pixel (1: pixel centres, more: jittered)")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  if (scope.threads) {
    render.add_option("--threads,-j", args.threads, "Worker threads (0: all cores)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
  }
  render.add_option("--seed", args.seed, "Seed of the sample jitter (0 to 2^64 - 1)")
      ->check(seed_range())
      ->capture_default_str();
  render.add_option("--max-depth", args.max_depth, "Path mode: rays per path at most")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  if (scope.time_limit) {
    render
        .add_option("--time-limit", args.time_limit,
                    "Path mode: seconds after which no sample is started (0: none); every pixel "
                    "gets the same samples, at least one")
        ->check(seconds_validator())
        ->capture_default_str();
  }
  render.add_option("-o,--output", args.output, "Output image, .png or .ppm")
      ->capture_default_str();
  if (scope.accel) {
    render
        .add_option("--accel", args.accel,
                    "Sphere queries: a BVH from 128 spheres on (auto), always, or brute force")
        ->check(CLI::IsMember(accel_names()))
        ->capture_default_str();
  }
  render.add_flag("--quiet,-q", args.quiet, "No progress bar, no summary line");
  if (scope.force)
    render.add_flag("--force,-f", args.force, "Replace the output even if it is read-only");
}

}  // namespace sphray::render
