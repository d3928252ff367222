// sphray-mpi: the sphray renderer with the scene's spheres spread over the ranks of an MPI job.
//
//   mpirun -np 4 sphray-mpi render -s rtiow-final -m shaded -o shaded.png
//   sphray-mpi generate random:4194304 -o random4m.sphp      # a particle file
//   mpirun -np 4 sphray-mpi bench random4m.sphp              # read, build, trace: one line
//
// Every rank reads the scene and keeps the spheres of one region of space (spatial_share);
// each batch of rays the renderer traces is answered by all ranks together (DistributedScene),
// so the image is the single-process `sphray render`'s, byte for byte, whatever the rank count.
// Rank 0 writes the image and prints. Exit status as sphray's: 2 for bad usage or input, 1 for
// a failure while running; every rank exits with the same status, so none waits for another.
#include <mpi.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "render_args.hpp"
#include "sphray/mpi/distributed_scene.hpp"
#include "sphray/mpi/particle_file.hpp"
#include "sphray/mpi/spatial_split.hpp"
#include "sphray/render/image_file.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"

namespace {

using namespace sphray::render;
using sphray::mpi::DistributedScene;

constexpr int kExitIo = 1;
constexpr int kExitUsage = 2;

int rank_of(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

int size_of(MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  return size;
}

// One line on stderr, from rank 0 only: every rank meets the same error.
void report(const std::string& message) {
  if (rank_of(MPI_COMM_WORLD) == 0) std::fprintf(stderr, "sphray-mpi: %s\n", message.c_str());
}

// The renderer's queries answered by every rank's share of the spheres together.
class DistributedQueries final : public RayQueries {
 public:
  explicit DistributedQueries(const DistributedScene& scene) : scene_(scene) {}
  void intersect(std::span<const sphray::Ray> rays, std::span<sphray::Hit> hits) const override {
    scene_.intersect(rays, hits);
  }
  void occluded(std::span<const sphray::Ray> rays, std::span<bool> out) const override {
    scene_.occluded(rays, out);
  }
  bool collective() const override { return true; }

 private:
  const DistributedScene& scene_;
};

// The scene's spheres this rank keeps, with their ids in the scene.
DistributedScene distribute(const Scene& scene, MPI_Comm comm) {
  const sphray::SphereView all = scene.spheres.view();
  const std::vector<std::uint32_t> ids =
      sphray::mpi::spatial_share(all, rank_of(comm), size_of(comm));
  sphray::SphereSoA mine;
  mine.reserve(ids.size());
  for (std::uint32_t id : ids)
    mine.add(scene.spheres.center(id), scene.spheres.radius(id), scene.spheres.mask(id));
  return DistributedScene(comm, mine.view(), ids);
}

// Rank 0 opens the output before any ray is traced; the others learn whether it could.
std::unique_ptr<PendingImageFile> open_output(const std::string& path, MPI_Comm comm, int& status) {
  std::unique_ptr<PendingImageFile> output;
  status = 0;
  if (rank_of(comm) == 0) {
    try {
      output = std::make_unique<PendingImageFile>(path);
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "sphray-mpi: %s\n", e.what());
      status = kExitUsage;
    } catch (const IoError& e) {
      std::fprintf(stderr, "sphray-mpi: %s\n", e.what());
      status = kExitIo;
    }
  }
  MPI_Bcast(&status, 1, MPI_INT, 0, comm);
  return output;
}

void print_summary(const RenderArgs& args, const RenderOptions& options, const RenderStats& stats,
                   const DistributedScene& scene) {
  MPI_Comm comm = scene.comm();
  double reduce = scene.times().reduce, slowest_reduce = 0;
  unsigned long long bytes = scene.local_bytes(), largest = 0;
  MPI_Reduce(&reduce, &slowest_reduce, 1, MPI_DOUBLE, MPI_MAX, 0, comm);
  MPI_Reduce(&bytes, &largest, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, 0, comm);
  if (rank_of(comm) != 0) return;
  const std::uint64_t rays = stats.camera_rays + stats.bounce_rays + stats.shadow_rays;
  std::printf(
      "wrote %s: %dx%d, %d spp, %s, %d ranks, %.3f s, %.0f rays/s (%llu camera + %llu bounce + "
      "%llu shadow rays); %zu spheres, at most %llu bytes and %.3f s in reductions a rank\n",
      args.output.c_str(), options.width, options.height, stats.spp, args.mode.c_str(),
      size_of(comm), stats.seconds,
      stats.seconds > 0 ? static_cast<double>(rays) / stats.seconds : 0.0,
      static_cast<unsigned long long>(stats.camera_rays),
      static_cast<unsigned long long>(stats.bounce_rays),
      static_cast<unsigned long long>(stats.shadow_rays), scene.global_size(), largest,
      slowest_reduce);
}

int run_render(const RenderArgs& args, MPI_Comm comm) {
  if (!image_format_for(args.output)) {
    report(args.output + ": expected an output file ending in .png or .ppm");
    return kExitUsage;
  }
  try {
    // Deterministic on every rank: a scene or option error is met by all alike.
    const Scene scene = load_scene_or_preset(args.scene);
    RenderOptions options;
    options.mode = *parse_mode(args.mode);  // CLI11 checked the name
    options.width = args.width > 0 ? args.width : scene.width;
    options.height = args.height > 0 ? args.height : scene.height;
    options.spp = args.spp;
    options.seed = args.seed;
    options.max_depth = args.max_depth;
    int status = 0;
    std::unique_ptr<PendingImageFile> output = open_output(args.output, comm, status);
    if (status != 0) return status;
    const DistributedScene distributed = distribute(scene, comm);
    const DistributedQueries queries(distributed);
    RenderStats stats;
    const Image image = render(scene, queries, options, {}, &stats);
    if (output) output->commit(image);
    if (!args.quiet) print_summary(args, options, stats, distributed);
    return 0;
  } catch (const SceneError& e) {
    report(e.what());
    return kExitUsage;
  } catch (const std::invalid_argument& e) {
    report(e.what());
    return kExitUsage;
  } catch (const IoError& e) {
    std::fprintf(stderr, "sphray-mpi: %s\n", e.what());  // rank 0's alone: the others are done
    return kExitIo;
  }
}

// generate: a scene's spheres (a preset such as random:N, or a scene file) as a particle file.
// Rank 0 writes it; the other ranks, if any, have nothing to do.
int run_generate(const std::string& scene_name, const std::string& output, MPI_Comm comm) {
  if (rank_of(comm) != 0) return 0;
  try {
    const Scene scene = load_scene_or_preset(scene_name);
    sphray::mpi::write_particles(output, scene.spheres.view());
    return 0;
  } catch (const SceneError& e) {
    report(e.what());
    return kExitUsage;
  } catch (const sphray::mpi::ParticleFileError& e) {
    report(e.what());
    return kExitIo;
  }
}

struct BenchArgs {
  std::string particles;
  std::uint64_t rays = 1 << 20;
  std::size_t batch = 1 << 16;
  bool beside = false;  // rays that pass beside the box: what a rank's root alone costs
};

double max_over_ranks(double value, MPI_Comm comm) {
  double largest = 0;
  MPI_Allreduce(&value, &largest, 1, MPI_DOUBLE, MPI_MAX, comm);
  return largest;
}

// The box around every rank's spheres (centres padded by their radii).
std::pair<sphray::Vec3, sphray::Vec3> global_bounds(const sphray::SphereSoA& spheres,
                                                    MPI_Comm comm) {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::uint32_t i = 0; i < spheres.size(); ++i) {
    const sphray::Vec3 c = spheres.center(i);
    const float r = spheres.radius(i);
    const float v[3] = {c.x, c.y, c.z};
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(v[k]) || !(r > 0) || !std::isfinite(r)) continue;
      lo[k] = std::min(lo[k], v[k] - r);
      hi[k] = std::max(hi[k], v[k] + r);
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, lo, 3, MPI_FLOAT, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, hi, 3, MPI_FLOAT, MPI_MAX, comm);
  return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
}

// Ray i of a pinhole view of the box from in front (+z), on a square grid of side^2 rays: the
// same on every rank, from i alone. beside: the view is moved two box widths along +x, so that
// every ray passes the box (and each rank's tree rejects it at its root).
sphray::Ray view_ray(std::uint64_t i, std::uint64_t side, sphray::Vec3 lo, sphray::Vec3 hi,
                     bool beside) {
  const sphray::Vec3 center = 0.5f * (lo + hi);
  const float extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  const sphray::Vec3 eye{center.x, center.y, hi.z + extent};
  const float u = (static_cast<float>(i % side) + 0.5f) / static_cast<float>(side);
  const float v = (static_cast<float>(i / side) + 0.5f) / static_cast<float>(side);
  const float shift = beside ? 2.0f * extent : 0.0f;
  const sphray::Vec3 target{lo.x + shift + u * (hi.x - lo.x), lo.y + v * (hi.y - lo.y), hi.z};
  return sphray::Ray{eye, target - eye};
}

// bench: reads a particle file over the ranks, builds, traces closest-hit rays in batches, and
// prints one line of figures (the slowest rank's where ranks differ).
int run_bench(const BenchArgs& args, MPI_Comm comm) {
  try {
    MPI_Barrier(comm);
    double start = MPI_Wtime();
    const sphray::mpi::ParticleShare share = sphray::mpi::read_particle_share(comm, args.particles);
    const double read_seconds = max_over_ranks(MPI_Wtime() - start, comm);
    const DistributedScene scene(comm, share.spheres.view(), share.ids);
    const double build_seconds = max_over_ranks(scene.build_seconds(), comm);
    const double bytes = max_over_ranks(static_cast<double>(scene.local_bytes()), comm);
    const auto [lo, hi] = global_bounds(share.spheres, comm);
    const auto side =
        static_cast<std::uint64_t>(std::ceil(std::sqrt(static_cast<double>(args.rays))));
    std::vector<sphray::Ray> rays(args.batch);
    std::vector<sphray::Hit> hits(args.batch);
    std::uint64_t found = 0;
    MPI_Barrier(comm);
    start = MPI_Wtime();
    for (std::uint64_t first = 0; first < args.rays; first += args.batch) {
      const std::size_t n =
          static_cast<std::size_t>(std::min<std::uint64_t>(args.batch, args.rays - first));
      for (std::size_t k = 0; k < n; ++k)
        rays[k] = view_ray(first + k, side, lo, hi, args.beside);
      scene.intersect(std::span(rays.data(), n), std::span(hits.data(), n));
      for (std::size_t k = 0; k < n; ++k)
        found += hits[k].found() ? 1 : 0;
    }
    const double trace_seconds = max_over_ranks(MPI_Wtime() - start, comm);
    const double reduce_seconds = max_over_ranks(scene.times().reduce, comm);
    const double local_seconds = max_over_ranks(scene.times().local, comm);
    if (rank_of(comm) == 0) {
      std::printf("| %d | %zu | %.1f | %.2f | %.2f | %.3g | %.2f | %.2f | %.1f%% |\n",
                  size_of(comm), scene.global_size(), bytes / (1 << 20), read_seconds,
                  build_seconds, static_cast<double>(args.rays) / trace_seconds, local_seconds,
                  reduce_seconds,
                  100.0 * static_cast<double>(found) / static_cast<double>(args.rays));
    }
    return 0;
  } catch (const sphray::mpi::ParticleFileError& e) {
    report(e.what());
    return kExitUsage;
  }
}

int run(int argc, char** argv, MPI_Comm comm) {
  CLI::App app{"sphray-mpi: render with the spheres spread over MPI ranks", "sphray-mpi"};
  app.require_subcommand(1, 1);
  RenderArgs render_args;
  CLI::App* render = app.add_subcommand("render", "Render a scene; rank 0 writes the image");
  // One process's threads, clock and file policy have no meaning across ranks: the tiles run
  // in order on each rank, and a time limit would differ between clocks.
  add_render_options(*render, render_args,
                     {.threads = false, .time_limit = false, .accel = false, .force = false});
  std::string generate_scene, generate_output;
  CLI::App* generate =
      app.add_subcommand("generate", "Write a scene's spheres (e.g. random:N) as a particle file");
  generate->add_option("scene", generate_scene, "A preset (random:N) or a .json scene")->required();
  generate->add_option("-o,--output", generate_output, "The particle file to write")->required();
  BenchArgs bench_args;
  CLI::App* bench = app.add_subcommand(
      "bench", "Read a particle file over the ranks, build, trace; print one table row");
  bench->add_option("particles", bench_args.particles, "A particle file")->required();
  bench->add_option("--rays", bench_args.rays, "Closest-hit rays to trace")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 32))
      ->capture_default_str();
  bench->add_option("--batch", bench_args.batch, "Rays per reduction")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 24))
      ->capture_default_str();
  bench->add_flag("--beside", bench_args.beside,
                  "Aim every ray beside the spheres: the cost of a tree's root alone");
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return rank_of(comm) == 0 ? app.exit(e) : 0;
  } catch (const CLI::ParseError& e) {
    const std::string message = e.what();
    report(message.substr(0, message.find('\n')) + " (see sphray-mpi --help)");
    return kExitUsage;
  }
  if (*render) return run_render(render_args, comm);
  if (*generate) return run_generate(generate_scene, generate_output, comm);
  if (*bench) return run_bench(bench_args, comm);
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int status = kExitIo;
  try {
    status = run(argc, argv, MPI_COMM_WORLD);
  } catch (const std::exception& e) {
    // Unexpected, and perhaps on one rank alone: end the whole job rather than leave the
    // others waiting in a reduction.
    std::fprintf(stderr, "sphray-mpi: rank %d: %s\n", rank_of(MPI_COMM_WORLD), e.what());
    MPI_Abort(MPI_COMM_WORLD, kExitIo);
  }
  MPI_Finalize();
  return status;
}
