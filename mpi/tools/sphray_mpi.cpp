// sphray-mpi: the sphray renderer with the scene's spheres spread over the ranks of an MPI job.
//
//   mpirun -np 4 sphray-mpi render -s rtiow-final -m shaded -o shaded.png
//
// Every rank reads the scene and keeps the spheres of one region of space (spatial_share);
// each batch of rays the renderer traces is answered by all ranks together (DistributedScene),
// so the image is the single-process `sphray render`'s, byte for byte, whatever the rank count.
// Rank 0 writes the image and prints. Exit status as sphray's: 2 for bad usage or input, 1 for
// a failure while running; every rank exits with the same status, so none waits for another.
#include <mpi.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <string>

#include "sphray/mpi/distributed_scene.hpp"
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

struct RenderArgs {
  std::string scene = "rtiow-final";
  std::string mode = "normals";
  int width = 0, height = 0;  // 0: the scene's own size
  int spp = 4;
  std::uint64_t seed = 0;
  int max_depth = 50;
  std::string output = "sphray.png";
  bool quiet = false;
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

void add_render_options(CLI::App& render, RenderArgs& args) {
  render.add_option("--scene,-s", args.scene, "A preset or a .json file (as sphray render)")
      ->capture_default_str();
  render.add_option("--mode,-m", args.mode, "What to show")
      ->check(CLI::IsMember(mode_names()))
      ->capture_default_str();
  render.add_option("--width,-W", args.width, "Image width (default: the scene's)")
      ->check(CLI::Range(1, kMaxImageSide));
  render.add_option("--height,-H", args.height, "Image height (default: the scene's)")
      ->check(CLI::Range(1, kMaxImageSide));
  render.add_option("--spp", args.spp, "Samples per pixel")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  render.add_option("--seed", args.seed, "Seed of the samples")->capture_default_str();
  render.add_option("--max-depth", args.max_depth, "Path mode: rays per path at most")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  render.add_option("-o,--output", args.output, "Output image, .png or .ppm (rank 0 writes it)")
      ->capture_default_str();
  render.add_flag("--quiet,-q", args.quiet, "No summary line");
}

int run(int argc, char** argv, MPI_Comm comm) {
  CLI::App app{"sphray-mpi: render with the spheres spread over MPI ranks", "sphray-mpi"};
  app.require_subcommand(1, 1);
  RenderArgs render_args;
  CLI::App* render = app.add_subcommand("render", "Render a scene; rank 0 writes the image");
  add_render_options(*render, render_args);
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
