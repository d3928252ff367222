// The sphray command: render, bench, convert, scenes, info. A thin shell over sphray::render; every
// failure is one line on stderr and an exit status: 2 for bad usage or input (refused before any
// work), 1 for a failure during the run (I/O, memory). No exception leaves main.
#include <sys/resource.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <new>
#include <string>
#include <thread>

#include "bench/bench_command.hpp"
#include "command/command_failure.hpp"
#include "command/convert_command.hpp"
#include "command/progress_report.hpp"
#include "command/render_args.hpp"
#include "frame/scene_queries.hpp"
#include "sphray/render/image_file.hpp"
#include "sphray/render/memory_check.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"
#include "sphray/sphray.hpp"

namespace {

using namespace sphray::render;

// Standard output is flushed and checked before the exit status is decided: `sphray scenes >
// /dev/full` or a closed stdout is a failed run, not a silent success.
int flush_stdout(int status) {
  errno = 0;
  std::cout.flush();
  const bool failed = std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout;
  if (!failed) return status;
  const int error = errno;
  report(std::string("standard output: cannot write (") +
         (error != 0 ? std::strerror(error) : "write error") + ")");
  return status == 0 ? kExitIo : status;
}

// The size asked for: the scene's, or with one side given, the other in the scene's aspect
// (floored, as the scene file's rule does it), within 1..kMaxImageSide.
void choose_size(const RenderArgs& args, const Scene& scene, RenderOptions& options) {
  auto other_side = [](int given, int scene_given, int scene_other) {
    const long long side = static_cast<long long>(given) * scene_other / scene_given;
    return static_cast<int>(std::clamp<long long>(side, 1, kMaxImageSide));
  };
  options.width = args.width > 0    ? args.width
                  : args.height > 0 ? other_side(args.height, scene.height, scene.width)
                                    : scene.width;
  options.height = args.height > 0  ? args.height
                   : args.width > 0 ? other_side(args.width, scene.width, scene.height)
                                    : scene.height;
}

// Worker threads: more than the machine runs at once buys nothing, and oneTBB warns on stderr
// (even under --quiet) when asked for more workers than it allows; the image is the same.
int worker_threads(int requested) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return requested == 0 ? 0 : std::min(requested, cores);
}

// Memory for the image and for encoding it, and headroom for the worker threads' stacks and
// the allocator: checked before the render, so a render that cannot finish is not started.
void require_image_memory(const RenderArgs& args, const RenderOptions& options) {
  constexpr std::size_t kMiB = std::size_t{1} << 20;
  const std::size_t threads = options.threads > 0
                                  ? static_cast<std::size_t>(options.threads)
                                  : std::max(1u, std::thread::hardware_concurrency());
  // Path mode also keeps every pixel's radiance in float twice: the sums and the means.
  const std::size_t path_buffers = options.mode == Mode::path
                                       ? 2 * sizeof(sphray::Vec3) *
                                             static_cast<std::size_t>(options.width) *
                                             static_cast<std::size_t>(options.height)
                                       : 0;
  const std::size_t bytes =
      encoding_peak_bytes(*image_format_for(args.output), options.width, options.height) +
      path_buffers + 64 * kMiB + threads * 8 * kMiB;
  require_memory(bytes, args.output + ": a " + std::to_string(options.width) + "x" +
                            std::to_string(options.height) + " image");
}

// The first phase's name: a preset is made, a file (or standard input) read.
std::string scene_phase(const std::string& scene) {
  if (scene == "-") return "reading the scene from standard input";
  const std::vector<std::string> presets = preset_names();
  const bool preset = scene.starts_with("random:") ||
                      std::find(presets.begin(), presets.end(), scene) != presets.end();
  return (preset ? "making the scene " : "reading ") + scene;
}

// Whether render() builds a tree before it traces (SceneQueries' rule): a phase of its own.
bool builds_tree(const Scene& scene, const RenderOptions& options) {
  return options.accel == Accel::bvh || (options.accel == Accel::automatic &&
                                         scene.spheres.size() >= SceneQueries::kBvhFromSpheres);
}

void print_summary(const RenderArgs& args, const RenderOptions& options, const RenderStats& s) {
  std::uint64_t rays = s.camera_rays + s.bounce_rays + s.shadow_rays;
  double rate = s.seconds > 0 ? static_cast<double>(rays) / s.seconds : 0.0;
  char accel[48] = "brute force";
  if (s.bvh) std::snprintf(accel, sizeof accel, "bvh built in %.3f s", s.build_seconds);
  std::printf(
      "wrote %s: %dx%d, %d spp, %s, %.3f s, %s (%llu camera + %llu bounce + %llu shadow rays, "
      "%s)\n",
      args.output.c_str(), options.width, options.height, s.spp, args.mode.c_str(), s.seconds,
      progress::rate_text(rate).c_str(), static_cast<unsigned long long>(s.camera_rays),
      static_cast<unsigned long long>(s.bounce_rays),
      static_cast<unsigned long long>(s.shadow_rays), accel);
  if (options.mode == Mode::path && s.kernel_seconds > 0) {
    std::printf(
        "path: max depth %d%s; thread time %.3f s, %.1f%% in the kernel, renderer "
        "overhead %.1f%% of kernel time\n",
        options.max_depth, s.spp < options.spp ? " (time limit reached)" : "", s.trace_seconds,
        100.0 * s.kernel_seconds / s.trace_seconds,
        100.0 * (s.trace_seconds - s.kernel_seconds) / s.kernel_seconds);
  }
}

// Where a render's wall time went, for the second summary line: what a user of a large particle
// file needs to see (docs/performance.md, "Particles at scale", reads it).
struct Phases {
  using Clock = std::chrono::steady_clock;
  Clock::time_point start = Clock::now();
  double scene = 0, write = 0;
  std::size_t spheres = 0;

  static double since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  }
};

// The most memory the process has held, in bytes (Linux reports kilobytes).
double peak_resident_bytes() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) * 1024.0;
}

void print_phases(const RenderStats& s, const Phases& p, double total) {
  const double peak = peak_resident_bytes();
  // Per sphere only where the spheres, not the program and the image, make most of the memory.
  char per_sphere[48] = "";
  if (p.spheres >= 10000)
    std::snprintf(per_sphere, sizeof per_sphere, " (%.1f bytes per sphere)",
                  peak / static_cast<double>(p.spheres));
  std::printf(
      "phases: scene %.3f s, tree %.3f s, render %.3f s, write %.3f s; first image in %.3f s; "
      "peak memory %.1f MB%s\n",
      p.scene, s.build_seconds, s.seconds, p.write, total, peak / 1e6, per_sphere);
}

int run_render(const RenderArgs& args) {
  // Everything that can be refused is refused before the scene is built or a ray is traced.
  if (!image_format_for(args.output)) {
    report(args.output + ": expected an output file ending in .png or .ppm");
    return kExitUsage;
  }
  if (args.precision == "double" && args.mode == "path") {
    report(
        "--precision double: expected a mode other than path (the path tracer traces in "
        "float; docs/double.md, \"The command\")");
    return kExitUsage;
  }
  try {
    Phases phases;
    progress::Reporter reporter(!args.quiet, ::isatty(STDERR_FILENO) == 1, args.time_limit);
    reporter.phase(scene_phase(args.scene));
    Scene scene = load_scene_or_preset(args.scene, scene_options(args));
    apply_camera(args.camera, scene);
    phases.scene = Phases::since(phases.start);
    phases.spheres = scene.spheres.size();
    RenderOptions options;
    options.mode = *parse_mode(args.mode);  // CLI11 checked the name
    choose_size(args, scene, options);
    options.spp = args.spp;
    options.threads = worker_threads(args.threads);
    options.seed = args.seed;
    options.max_depth = args.max_depth;
    options.time_limit = args.time_limit;
    options.accel = *parse_accel(args.accel);              // CLI11 checked the name
    options.precision = *parse_precision(args.precision);  // CLI11 checked the name
    PendingImageFile output(args.output, args.force);
    require_image_memory(args, options);
    RenderStats stats;
    reporter.phase(builds_tree(scene, options)
                       ? "building the tree of " + std::to_string(scene.spheres.size()) + " spheres"
                       : "rendering");
    const Image image = render(
        scene, options,
        [&reporter](std::size_t done, std::size_t total, const RayCounts& rays) {
          reporter.update(done, total, rays);
        },
        &stats);
    reporter.phase("writing " + args.output);
    const auto write_start = Phases::Clock::now();
    output.commit(image);
    phases.write = Phases::since(write_start);
    const double total = Phases::since(phases.start);
    reporter.finish();
    if (!args.quiet) {
      print_summary(args, options, stats);
      print_phases(stats, phases, total);
    }
    return 0;
  } catch (...) {
    // The estimate leaves headroom, but a scene of millions of spheres or another process can
    // still take what was there; the pending file is gone by now (its destructor ran).
    return report_failure(args.scene + ": out of memory while building or rendering the scene");
  }
}

int run_scenes() {
  std::vector<std::string> names = preset_names();
  std::vector<std::string> descriptions = preset_descriptions();
  for (std::size_t i = 0; i < names.size(); ++i) {
    std::printf("%-12s %s\n", names[i].c_str(), descriptions[i].c_str());
  }
  std::printf("%-12s a scene file (format: docs/scenes.md)\n", "FILE.json");
  return 0;
}

// The trees' instruction set by size, e.g. "avx2; from 1024 spheres: avx512": the sizes where
// bvh_isa(n) changes, found by bisection between powers of two.
std::string tree_isas() {
  const auto name = [](std::size_t n) { return std::string(sphray::isa_name(sphray::bvh_isa(n))); };
  std::string text = name(0);
  std::size_t lo = 0;
  for (std::size_t hi = 1; hi <= (std::size_t{1} << 40); hi *= 2) {
    if (name(hi) == name(lo)) {
      lo = hi;
      continue;
    }
    std::size_t a = lo, b = hi;  // name(a) != name(b): the first n in (a, b] that changes
    while (b - a > 1) {
      const std::size_t mid = a + (b - a) / 2;
      (name(mid) == name(a) ? a : b) = mid;
    }
    text += "; from " + std::to_string(b) + " spheres: " + name(b);
    lo = b;
    hi = b;
  }
  return text;
}

int run_info() {
  std::printf("sphray %s\n", sphray::kVersion);
  std::printf("instruction set: %s\n", std::string(sphray::isa_name(sphray::active_isa())).c_str());
  std::string supported;
  for (sphray::Isa isa : sphray::supported_isas()) {
    supported += (supported.empty() ? "" : ", ") + std::string(sphray::isa_name(isa));
  }
  std::printf("supported here: %s (choose with SPHRAY_ISA)\n", supported.c_str());
  std::printf("trees: %s\n", tree_isas().c_str());
  return 0;
}

// A number of seconds from 0 to 1e9: CLI::Range lets NaN through and prints its bounds as %f.
void add_bench_options(CLI::App& bench, sphray::render::bench::BenchArgs& args) {
  bench.add_option("--scene,-s", args.scene, "A preset (see `sphray scenes`) or a .json file")
      ->capture_default_str();
  bench
      .add_option("--rays", args.rays, "Camera rays (coherent), random rays (incoherent), or both")
      ->check(CLI::IsMember(std::vector<std::string>{"camera", "random", "both"}))
      ->capture_default_str();
  bench.add_option("--threads,-j", args.threads, "Threads each row traces on")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  bench
      .add_option("--seconds", args.seconds,
                  "Seconds of passes over the rays per row, shared among its repetitions")
      ->check(seconds_validator())
      ->capture_default_str();
  bench
      .add_option("--repetitions", args.repetitions,
                  "Times each row is timed: its rate is their median, its spread min to max")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  bench
      .add_option("--query", args.query,
                  "What each row answers: the closest hit, or every crossing (count_hits, "
                  "intersect_all and intersect_nearest into 16 slots, and Embree's multi-hit "
                  "filters)")
      ->check(CLI::IsMember(std::vector<std::string>{"closest", "every-hit"}))
      ->capture_default_str();
  add_camera_options(bench, args.camera);  // the camera rays' camera
  bench.add_option("--json", args.json, "Also write the results as Google Benchmark JSON");
  bench.add_flag("--force,-f", args.force, "Replace the --json file even if it is read-only");
  bench.add_flag("--quiet,-q", args.quiet, "No progress line on stderr");
}

int run(int argc, char** argv) {
  CLI::App app{"sphray: render spheres with the sphray kernel", "sphray"};
  app.set_version_flag("--version", std::string(sphray::kVersion));
  app.require_subcommand(0, 1);
  RenderArgs args;
  CLI::App* render = app.add_subcommand("render", "Render a scene to a PNG or PPM image");
  add_render_options(*render, args);
  sphray::render::bench::BenchArgs bench_args;
  CLI::App* bench = app.add_subcommand(
      "bench",
      "Rays per second of each instruction set's brute force, tree and stream (and "
      "Embree's, where built with it) on a scene, each checked against the scalar "
      "reference first");
  add_bench_options(*bench, bench_args);
  sphray::render::convert::ConvertArgs convert_args;
  CLI::App* convert = app.add_subcommand(
      "convert",
      "Write the spheres of a scene or particle file as a particle file (.sphp, .xyz, .csv, .ply)");
  add_convert_options(*convert, convert_args);
  CLI::App* scenes = app.add_subcommand("scenes", "List the preset scenes");
  CLI::App* info = app.add_subcommand("info", "Print the version and the instruction set in use");
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    std::string message = e.what();
    report(message.substr(0, message.find('\n')) + " (see sphray --help)");
    return kExitUsage;
  }
  if (*scenes) return run_scenes();
  if (*info) return run_info();
  if (*render) return run_render(args);
  if (*convert) return sphray::render::convert::run_convert(convert_args);
  if (*bench) {
    bench_args.threads = std::min(bench_args.threads, worker_threads(bench_args.threads));
    return sphray::render::bench::run_bench(bench_args);
  }
  std::cout << app.help();
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  // Before any temporary exists: a fatal signal removes it (an ignored one stays ignored).
  remove_temporaries_on_signals();
  int status = kExitIo;
  try {
    status = run(argc, argv);
  } catch (const std::bad_alloc&) {
    report("out of memory");
  } catch (const std::exception& e) {
    report(std::string("unexpected error: ") + e.what());
  } catch (...) {
    report("unexpected error");
  }
  return flush_stdout(status);
}
