// sphray-mpi: the sphray renderer with the scene's spheres spread over the ranks of an MPI job.
//
//   mpirun -np 4 sphray-mpi render -s rtiow-final -m shaded -o shaded.png
//   sphray-mpi generate random:4194304 -o random4m.sphp      # a particle file
//   mpirun -np 4 sphray-mpi bench random4m.sphp              # read, build, trace: one line
//
// Two ways to share the work (--distribution, docs/distributed.md). Replicated: every rank
// builds the whole scene and renders every rank-th tile of the image on its own; rank 0 adds
// the shares up. Split: every rank keeps the spheres of one region of space (plane_shares)
// and each batch of rays the renderer traces is answered by all ranks together
// (DistributedScene). Either way the image is the single-process `sphray render`'s, byte for
// byte, whatever the rank count. auto, the default, replicates when the whole scene's tree fits
// each rank's share of its node's free memory.
// Rank 0 writes the image and prints. Exit status as sphray's: 2 for bad usage or input, 1 for
// a failure while running; every rank exits with the same status, so none waits for another.
// Before any work the ranks agree: on whether any of them met an error (the lowest such rank's
// message is printed, once), and on their input (the subcommand, the scene, the options), so
// that an MPMD launch or a node-local file that differs between nodes is refused, not traced.
#include <mpi.h>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "command/render_args.hpp"
#include "image/atomic_output.hpp"
#include "sphray/mpi/agreement.hpp"
#include "sphray/mpi/distributed_scene.hpp"
#include "sphray/mpi/particle_file.hpp"
#include "sphray/mpi/spatial_split.hpp"
#include "sphray/render/camera.hpp"
#include "sphray/render/image_file.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"
#include "view_rays.hpp"

namespace {

using namespace sphray::render;
using sphray::mpi::DistributedScene;
using sphray::mpi::RankError;
using sphray::mpi::Setting;
using sphray::mpi::tools::axis_of;
using sphray::mpi::tools::box_of;
using sphray::mpi::tools::view_ray;

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

// The status every rank exits with, given this rank's error ({0, ""}: none): the lowest failing
// rank's, whose message rank 0 prints (naming that rank if it is another). Collective.
int agreed_status(const RankError& mine, MPI_Comm comm) {
  const RankError first = sphray::mpi::first_error(comm, mine);
  if (first.status != 0 && rank_of(comm) == 0) {
    const std::string from = first.rank != 0 ? "rank " + std::to_string(first.rank) + ": " : "";
    std::fprintf(stderr, "sphray-mpi: %s%s\n", from.c_str(), first.message.c_str());
  }
  return first.status;
}

// 0 if every rank holds the same settings; otherwise kExitUsage on every rank, after rank 0 names
// the settings that differ. Collective.
int refuse_disagreement(std::span<const Setting> settings, MPI_Comm comm) {
  const std::vector<sphray::mpi::Disagreement> differing =
      sphray::mpi::disagreements(comm, settings);
  if (differing.empty()) return 0;
  report("the ranks' input differs in " + sphray::mpi::describe(differing) +
         " (every rank must be given the same scene and options)");
  return kExitUsage;
}

// A hash of everything in a scene that the image depends on: the spheres (centres, radii,
// masks), their colours and materials, the sky and the camera.
std::uint64_t scene_hash(const Scene& scene) {
  sphray::mpi::Fnv1a hash;
  for (std::uint32_t i = 0; i < scene.spheres.size(); ++i) {
    hash.add_value(scene.spheres.center(i));
    hash.add_value(scene.spheres.radius(i));
    hash.add_value(scene.spheres.mask(i));
  }
  hash.add_value(scene.colors.size());  // the counts keep colours and materials apart
  hash.add_value(scene.materials.size());
  for (const sphray::Vec3& color : scene.colors)
    hash.add_value(color);
  for (const Material& m : scene.materials) {
    hash.add_value(m.kind);
    hash.add_value(m.albedo);
    hash.add_value(m.fuzz);
    hash.add_value(m.ior);
  }
  hash.add_value(scene.default_material.kind);  // --material: every particle's
  hash.add_value(scene.default_material.fuzz);
  hash.add_value(scene.default_material.ior);
  hash.add_value(scene.sky.horizon);
  hash.add_value(scene.sky.zenith);
  const CameraSpec& c = scene.camera;
  for (const sphray::Vec3& v : {c.lookfrom, c.lookat, c.vup})
    hash.add_value(v);
  for (float f : {c.vfov, c.defocus_angle, c.focus_dist})
    hash.add_value(f);
  return hash.value();
}

// The renderer's queries answered by every rank's share of the spheres together: shared
// batches (every rank the same rays), or routed (every rank its own rays, each sent only to the
// regions it crosses).
class DistributedQueries final : public RayQueries {
 public:
  DistributedQueries(const DistributedScene& scene, bool routed) : scene_(scene), routed_(routed) {}
  void intersect(std::span<const sphray::Ray> rays, std::span<sphray::Hit> hits) const override {
    if (routed_)
      scene_.intersect_routed(rays, hits);
    else
      scene_.intersect(rays, hits);
  }
  void occluded(std::span<const sphray::Ray> rays, std::span<bool> out) const override {
    if (routed_)
      scene_.occluded_routed(rays, out);
    else
      scene_.occluded(rays, out);
  }
  bool collective() const override { return true; }
  bool uneven_calls() const override { return routed_; }
  void finish() const override {
    if (routed_) scene_.finish_routed();
  }

 private:
  const DistributedScene& scene_;
  bool routed_;
};

// The tiles rank `rank` renders when routed: those whose centre ray enters its region first, so
// that a rank traces its own camera rays in its own tree and sends on only the rays that leave
// it; tiles whose centre ray meets no region (the sky) dealt one in ranks. With the cuts placed
// by the camera's rays (take_share), a cloud's ranks get about equal numbers of tiles. Where
// they do not (a region that wraps the others, as rtiow-final's ground does, comes first for
// nearly every ray), one tile in ranks: the interleaved shares cost about the same however the
// cost varies across the image, which one rank's region of the image would not.
TileShare tiles_by_region(const Scene& scene, const RenderOptions& options,
                          const DistributedScene& distributed, int rank, int ranks) {
  const Camera view(scene.camera, options.width, options.height);
  const std::size_t tiles = tile_count(options.width, options.height);
  std::vector<std::uint32_t> mine;
  std::vector<std::size_t> counts(static_cast<std::size_t>(ranks));
  std::size_t sky = 0;
  for (std::size_t t = 0; t < tiles; ++t) {
    const TileRect rect = tile_rect(t, options.width, options.height);
    const sphray::Ray centre =
        view.ray(static_cast<float>(rect.x0) + 0.5f * static_cast<float>(rect.width),
                 static_cast<float>(rect.y0) + 0.5f * static_cast<float>(rect.height));
    const int first =
        sphray::mpi::next_region(distributed.regions(), centre, centre.tmax, {}).region;
    const auto owner =
        first >= 0 ? static_cast<std::size_t>(first) : sky++ % static_cast<std::size_t>(ranks);
    ++counts[owner];
    if (owner == static_cast<std::size_t>(rank)) mine.push_back(static_cast<std::uint32_t>(t));
  }
  // Within a quarter of an equal share, each.
  const double equal = static_cast<double>(tiles) / ranks;
  for (std::size_t count : counts)
    if (std::abs(static_cast<double>(count) - equal) > 0.25 * equal) return TileShare(rank, ranks);
  return TileShare(rank, ranks, std::move(mine));
}

// The scene's spheres this rank keeps, with their ids in the scene: its cell of a split by
// planes, whose regions overlap least, cut across the camera's view (along its horizontal
// axis, so that every row of the image crosses every region) where it halves the camera's rays,
// not the spheres: of a coarse grid of camera rays, each cell's share enters its box first
// (docs/distributed.md, "Cut across the view"). Throws std::bad_alloc.
void take_share(const Scene& scene, const RenderOptions& options, MPI_Comm comm,
                sphray::SphereSoA& mine, std::vector<std::uint32_t>& ids) {
  const CameraSpec& camera = scene.camera;
  const sphray::Vec3 across =
      sphray::normalize(sphray::cross(camera.vup, camera.lookfrom - camera.lookat));
  const bool usable = std::isfinite(across.x) && std::isfinite(across.y) && std::isfinite(across.z);
  const sphray::Vec3 weights =
      usable ? sphray::Vec3{std::abs(across.x), std::abs(across.y), std::abs(across.z)}
             : sphray::Vec3{1, 1, 1};
  constexpr int kProbesAcross = 32;
  const int down = std::max(1, kProbesAcross * options.height / options.width);
  const Camera view(camera, kProbesAcross, down);
  std::vector<sphray::Ray> probes;
  for (int y = 0; y < down; ++y)
    for (int x = 0; x < kProbesAcross; ++x)
      probes.push_back(view.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f));
  ids =
      sphray::mpi::plane_share(scene.spheres.view(), rank_of(comm), size_of(comm), weights, probes);
  mine.reserve(ids.size());
  for (std::uint32_t id : ids)
    mine.add(scene.spheres.center(id), scene.spheres.radius(id), scene.spheres.mask(id));
}

// Rank 0 opens the output before any ray is traced; the others learn whether it could.
std::unique_ptr<PendingImageFile> open_output(const std::string& path, bool force, MPI_Comm comm,
                                              int& status) {
  std::unique_ptr<PendingImageFile> output;
  status = 0;
  if (rank_of(comm) == 0) {
    try {
      output = std::make_unique<PendingImageFile>(path, force);
    } catch (const std::invalid_argument& e) {  // OutputRefused among them
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

// Collective whatever rank 0's --quiet, which only decides whether it prints. Routed: every rank
// traced its own rays, so the counts are summed and the slowest rank's time taken; shared: every
// rank traced every ray, rank 0's figures are all.
void print_summary(const RenderArgs& args, const RenderOptions& options, const RenderStats& stats,
                   const DistributedScene& scene, bool routed) {
  MPI_Comm comm = scene.comm();
  double times[2] = {scene.times().reduce, stats.seconds}, slowest[2] = {0, 0};
  unsigned long long bytes = scene.local_bytes(), largest = 0;
  unsigned long long rays[4] = {stats.camera_rays, stats.bounce_rays, stats.shadow_rays,
                                scene.route_counts().traced},
                     all[4] = {0, 0, 0, 0};
  MPI_Reduce(times, slowest, 2, MPI_DOUBLE, MPI_MAX, 0, comm);
  MPI_Reduce(&bytes, &largest, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, 0, comm);
  MPI_Reduce(rays, all, 4, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, comm);
  unsigned long long busiest = 0;  // the most rays one rank traced in its tree
  MPI_Reduce(&rays[3], &busiest, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, 0, comm);
  if (rank_of(comm) != 0 || args.quiet) return;
  if (!routed) std::copy(rays, rays + 3, all);
  const double total = static_cast<double>(all[0] + all[1] + all[2]);
  const double seconds = routed ? slowest[1] : stats.seconds;
  std::printf(
      "wrote %s: %dx%d, %d spp, %s, %d ranks%s, %.3f s, %.0f rays/s (%llu camera + %llu bounce + "
      "%llu shadow rays); %zu spheres, at most %llu bytes and %.3f s in %s a rank",
      args.output.c_str(), options.width, options.height, stats.spp, args.mode.c_str(),
      size_of(comm),
      !routed                ? ""
      : options.share.listed ? " (routed, tiles by region)"
                             : " (routed)",
      seconds, seconds > 0 ? total / seconds : 0.0, all[0], all[1], all[2], scene.global_size(),
      largest, slowest[0], routed ? "exchanges" : "reductions");
  if (routed) {
    std::printf("; %.3f rays traced in the trees a ray, %.3f in the busiest rank's",
                total > 0 ? static_cast<double>(all[3]) / total : 0.0,
                total > 0 ? static_cast<double>(busiest) / total : 0.0);
  }
  std::printf("\n");
}

// Rank 0 writes the image (output is null on the other ranks); every rank learns whether it
// could and returns the same status. Collective.
int commit_image(PendingImageFile* output, const Image& image, MPI_Comm comm) {
  RankError mine;
  if (output) {
    try {
      output->commit(image);
    } catch (const IoError& e) {
      mine = {kExitIo, e.what()};
    }
  }
  return agreed_status(mine, comm);
}

enum class Distribution { automatic, replicated, split, routed };

// Bytes a rank needs beyond the scene it has read to hold the whole scene's tree: the tree
// (under 40 a sphere, docs/bvh.md) and the build's records of the spheres.
constexpr double kTreeBytesPerSphere = 80.0;

// The ranks that share this rank's node (its memory and cores), as a communicator's size.
int ranks_on_node(MPI_Comm comm) {
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, rank_of(comm), MPI_INFO_NULL, &node);
  const int ranks = size_of(node);
  MPI_Comm_free(&node);
  return ranks;
}

// Whether every rank may hold the whole scene's tree: the node's free memory, halved for what
// else runs there, over its ranks. Collective: the ranks agree.
bool replicas_fit(std::size_t spheres, MPI_Comm comm) {
  const double free_bytes =
      static_cast<double>(sysconf(_SC_AVPHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  int fits =
      kTreeBytesPerSphere * static_cast<double>(spheres) * ranks_on_node(comm) <= 0.5 * free_bytes
          ? 1
          : 0;
  MPI_Allreduce(MPI_IN_PLACE, &fits, 1, MPI_INT, MPI_MIN, comm);
  return fits == 1;
}

// Sums the ranks' images (each black outside its tiles) into rank 0's. Collective.
void add_shares(Image& image, MPI_Comm comm) {
  std::uint8_t* data = image.rgb.data();
  for (std::size_t at = 0; at < image.rgb.size(); at += INT_MAX) {
    const int n = static_cast<int>(std::min<std::size_t>(INT_MAX, image.rgb.size() - at));
    MPI_Reduce(rank_of(comm) == 0 ? MPI_IN_PLACE : data + at, data + at, n, MPI_UNSIGNED_CHAR,
               MPI_SUM, 0, comm);
  }
}

// Replicated: this rank's share of the tiles over its own tree of the whole scene, on its share
// of the node's cores unless --threads says otherwise; the shares added up on rank 0.
Image render_replicated(const Scene& scene, RenderOptions options, MPI_Comm comm,
                        RenderStats& stats) {
  options.share = {rank_of(comm), size_of(comm)};
  if (options.threads == 0) {
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    options.threads = std::max(1, cores / ranks_on_node(comm));
  }
  Image image = render(scene, options, {}, &stats);
  add_shares(image, comm);
  return image;
}

// Collective whatever rank 0's --quiet, which only decides whether it prints.
void print_replicated_summary(const RenderArgs& args, const RenderOptions& options,
                              const RenderStats& stats, std::size_t spheres, MPI_Comm comm) {
  double seconds[2] = {stats.seconds, stats.build_seconds}, slowest[2] = {0, 0};
  unsigned long long rays[3] = {stats.camera_rays, stats.bounce_rays, stats.shadow_rays},
                     all[3] = {0, 0, 0};
  MPI_Reduce(seconds, slowest, 2, MPI_DOUBLE, MPI_MAX, 0, comm);
  MPI_Reduce(rays, all, 3, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, comm);
  if (rank_of(comm) != 0 || args.quiet) return;
  const double total = static_cast<double>(all[0] + all[1] + all[2]);
  std::printf(
      "wrote %s: %dx%d, %d spp, %s, %d ranks (replicated), %.3f s, %.0f rays/s (%llu camera + "
      "%llu bounce + %llu shadow rays); %zu spheres on every rank, tree built in %.3f s\n",
      args.output.c_str(), options.width, options.height, options.spp, args.mode.c_str(),
      size_of(comm), slowest[0], slowest[0] > 0 ? total / slowest[0] : 0.0, all[0], all[1], all[2],
      spheres, slowest[1]);
}

int run_render(const RenderArgs& args, Distribution distribution, MPI_Comm comm) {
  // Each rank reads the scene and checks the options; then the ranks agree on the outcome and
  // on the input before any collective the renderer makes.
  RankError mine;
  std::optional<Scene> scene;
  RenderOptions options;
  if (!image_format_for(args.output)) {
    mine = {kExitUsage, args.output + ": expected an output file ending in .png or .ppm"};
  } else {
    try {
      scene = load_scene_or_preset(args.scene, scene_options(args));
      apply_camera(args.camera, *scene);
      options.mode = *parse_mode(args.mode);  // CLI11 checked the name
      options.width = args.width > 0 ? args.width : scene->width;
      options.height = args.height > 0 ? args.height : scene->height;
      options.spp = args.spp;
      options.seed = args.seed;
      options.max_depth = args.max_depth;
    } catch (const SceneError& e) {
      mine = {kExitUsage, e.what()};
    } catch (const std::invalid_argument& e) {
      mine = {kExitUsage, e.what()};
    } catch (const std::bad_alloc&) {
      mine = {kExitIo, args.scene + ": out of memory while building the scene"};
    }
  }
  if (const int status = agreed_status(mine, comm)) return status;
  const Setting input[] = {
      {"the scene's sphere count", scene->spheres.size()},
      {"the scene (hash of its spheres, materials and camera)", scene_hash(*scene), false},
      {"--mode", static_cast<std::uint64_t>(options.mode)},
      {"the image width", static_cast<std::uint64_t>(options.width)},
      {"the image height", static_cast<std::uint64_t>(options.height)},
      {"--spp", static_cast<std::uint64_t>(options.spp)},
      {"--seed", options.seed},
      {"--distribution", static_cast<std::uint64_t>(distribution)},
      {"--max-depth", static_cast<std::uint64_t>(options.max_depth)}};
  if (const int status = refuse_disagreement(input, comm)) return status;

  int opened = 0;
  std::unique_ptr<PendingImageFile> output = open_output(args.output, args.force, comm, opened);
  if (opened != 0) return opened;
  if (distribution == Distribution::replicated ||
      (distribution == Distribution::automatic && replicas_fit(scene->spheres.size(), comm))) {
    options.threads = args.threads;
    RenderStats stats;
    const Image image = render_replicated(*scene, options, comm, stats);
    if (const int status = commit_image(output.get(), image, comm)) return status;
    print_replicated_summary(args, options, stats, scene->spheres.size(), comm);
    return 0;
  }
  sphray::SphereSoA share;
  std::vector<std::uint32_t> ids;
  mine = {};
  try {
    take_share(*scene, options, comm, share, ids);
  } catch (const std::bad_alloc&) {
    mine = {kExitIo, "out of memory taking this rank's share of " +
                         std::to_string(scene->spheres.size()) + " spheres"};
  }
  if (const int status = agreed_status(mine, comm)) return status;
  std::unique_ptr<DistributedScene> distributed;
  try {
    distributed = std::make_unique<DistributedScene>(comm, share.view(), ids);
  } catch (const std::invalid_argument& e) {  // the ranks agreed on it: every rank is here
    report(e.what());
    return kExitUsage;
  } catch (const std::runtime_error& e) {
    report(e.what());
    return kExitIo;
  }
  const bool routed = distribution == Distribution::routed;
  const DistributedQueries queries(*distributed, routed);
  RenderStats stats;
  if (routed)
    options.share = tiles_by_region(*scene, options, *distributed, rank_of(comm), size_of(comm));
  Image image = render(*scene, queries, options, {}, &stats);
  if (routed) add_shares(image, comm);
  if (const int status = commit_image(output.get(), image, comm)) return status;
  print_summary(args, options, stats, *distributed, routed);
  return 0;
}

// generate: a scene's spheres (a preset such as random:N, or a scene file) as a particle file.
// Rank 0 writes it, as `sphray render -o` writes an image: the output is checked before the
// scene is built (a read-only file is refused unless force) and replaced atomically, so a failure
// leaves it as it was. The other ranks, if any, wait for rank 0's status and exit with it.
int run_generate(const std::string& scene_name, const std::string& output, bool force,
                 MPI_Comm comm) {
  RankError mine;
  if (rank_of(comm) == 0) {
    try {
      sphray::render::detail::AtomicOutput file(output, force);
      const Scene scene = load_scene_or_preset(scene_name);
      sphray::mpi::write_particles(
          [&](const void* data, std::size_t size) { file.write(data, size); },
          scene.spheres.view());
      file.commit();
    } catch (const SceneError& e) {
      mine = {kExitUsage, e.what()};
    } catch (const std::invalid_argument& e) {  // OutputRefused among them
      mine = {kExitUsage, e.what()};
    } catch (const sphray::mpi::ParticleFileError& e) {
      mine = {kExitUsage, e.what()};
    } catch (const IoError& e) {
      mine = {kExitIo, e.what()};
    } catch (const std::bad_alloc&) {
      mine = {kExitIo, scene_name + ": out of memory while building the scene"};
    }
  }
  return agreed_status(mine, comm);
}

struct BenchArgs {
  std::string particles;
  std::uint64_t rays = 1 << 20;
  std::size_t batch = 1 << 16;
  bool beside = false;  // rays that pass beside the box: what a rank's root alone costs
  bool routed = false;  // each rank traces its share of a batch, routed to the regions it crosses
  std::string from = "z";  // the axis the view looks along, from its + side
};

double max_over_ranks(double value, MPI_Comm comm) {
  double largest = 0;
  MPI_Allreduce(&value, &largest, 1, MPI_DOUBLE, MPI_MAX, comm);
  return largest;
}

// The box around every rank's spheres.
std::pair<sphray::Vec3, sphray::Vec3> global_bounds(const sphray::SphereSoA& spheres,
                                                    MPI_Comm comm) {
  auto [lo, hi] = box_of(spheres);
  float low[3] = {lo.x, lo.y, lo.z}, high[3] = {hi.x, hi.y, hi.z};
  MPI_Allreduce(MPI_IN_PLACE, low, 3, MPI_FLOAT, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, high, 3, MPI_FLOAT, MPI_MAX, comm);
  return {{low[0], low[1], low[2]}, {high[0], high[1], high[2]}};
}

// The routed bench's line: rays per second, the slowest rank's tracing and exchanges, the rays
// each rank traced against all rays, and the exchanges per batch.
void print_routed_row(const DistributedScene& scene, const BenchArgs& args, double trace_seconds,
                      double local_seconds, double exchange_seconds, std::uint64_t found,
                      MPI_Comm comm) {
  unsigned long long counts[3] = {scene.route_counts().traced, found, scene.route_counts().sent};
  unsigned long long most_traced = counts[0];
  MPI_Allreduce(MPI_IN_PLACE, counts, 3, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, &most_traced, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, comm);
  if (rank_of(comm) != 0) return;
  const double rays = static_cast<double>(args.rays);
  const double batches = std::ceil(rays / static_cast<double>(args.batch));
  std::printf("| %d | %zu | %.3g | %.2f | %.2f | %.3f | %.3f | %.3f | %.1f | %.1f%% |\n",
              size_of(comm), scene.global_size(), rays / trace_seconds, local_seconds,
              exchange_seconds, static_cast<double>(most_traced) / rays,
              static_cast<double>(counts[0]) / rays, static_cast<double>(counts[2]) / rays,
              static_cast<double>(scene.route_counts().waves) / batches,
              100.0 * static_cast<double>(counts[1]) / rays);
}

// bench: reads a particle file over the ranks, builds, traces closest-hit rays in batches, and
// prints one line of figures (the slowest rank's where ranks differ).
// Shared batches (the default): every rank traces every ray, one reduction per batch. Routed
// (--routed): each rank its run of every batch, exchanged only with the regions it crosses.
int run_bench(const BenchArgs& args, MPI_Comm comm) {
  const Setting options[] = {{"--rays", args.rays},
                             {"--batch", static_cast<std::uint64_t>(args.batch)},
                             {"--beside", args.beside ? 1u : 0u},
                             {"--routed", args.routed ? 1u : 0u},
                             {"--from", static_cast<std::uint64_t>(axis_of(args.from))}};
  if (const int status = refuse_disagreement(options, comm)) return status;
  sphray::mpi::ParticleShare share;
  MPI_Barrier(comm);
  double start = MPI_Wtime();
  try {
    share = sphray::mpi::read_particle_share(comm, args.particles);  // the ranks agree in it
  } catch (const sphray::mpi::ParticleFileError& e) {
    report(e.what());
    return kExitUsage;
  }
  const double read_seconds = max_over_ranks(MPI_Wtime() - start, comm);
  std::unique_ptr<DistributedScene> built;
  try {
    built = std::make_unique<DistributedScene>(comm, share.spheres.view(), share.ids);
  } catch (const std::runtime_error& e) {  // out of memory: the ranks agreed, every rank is here
    report(args.particles + ": " + e.what());
    return kExitIo;
  }
  const DistributedScene& scene = *built;
  const double build_seconds = max_over_ranks(scene.build_seconds(), comm);
  const double bytes = max_over_ranks(static_cast<double>(scene.local_bytes()), comm);
  const auto [lo, hi] = global_bounds(share.spheres, comm);
  const auto side =
      static_cast<std::uint64_t>(std::ceil(std::sqrt(static_cast<double>(args.rays))));
  std::vector<sphray::Ray> rays;
  std::vector<sphray::Hit> hits;
  RankError mine;
  try {
    rays.resize(args.batch);
    hits.resize(args.batch);
  } catch (const std::bad_alloc&) {
    mine = {kExitIo, "out of memory for a batch of " + std::to_string(args.batch) + " rays"};
  }
  if (const int status = agreed_status(mine, comm)) return status;
  std::uint64_t found = 0;
  MPI_Barrier(comm);
  start = MPI_Wtime();
  const auto rank = static_cast<std::uint64_t>(rank_of(comm));
  const auto ranks = static_cast<std::uint64_t>(size_of(comm));
  for (std::uint64_t first = 0; first < args.rays; first += args.batch) {
    std::uint64_t n = std::min<std::uint64_t>(args.batch, args.rays - first);
    std::uint64_t begin = first;
    if (args.routed) {  // this rank's run of the batch
      begin = first + n * rank / ranks;
      n = first + n * (rank + 1) / ranks - begin;
    }
    for (std::size_t k = 0; k < n; ++k)
      rays[k] = view_ray(begin + k, side, lo, hi, axis_of(args.from), args.beside);
    const std::span<const sphray::Ray> batch(rays.data(), n);
    if (args.routed)
      scene.intersect_routed(batch, std::span(hits.data(), n));
    else
      scene.intersect(batch, std::span(hits.data(), n));
    for (std::size_t k = 0; k < n; ++k)
      found += hits[k].found() ? 1 : 0;
  }
  const double trace_seconds = max_over_ranks(MPI_Wtime() - start, comm);
  const double reduce_seconds = max_over_ranks(scene.times().reduce, comm);
  const double local_seconds = max_over_ranks(scene.times().local, comm);
  if (args.routed) {
    print_routed_row(scene, args, trace_seconds, local_seconds, reduce_seconds, found, comm);
    return 0;
  }
  if (rank_of(comm) == 0) {
    std::printf("| %d | %zu | %.1f | %.2f | %.2f | %.3g | %.2f | %.2f | %.1f%% |\n", size_of(comm),
                scene.global_size(), bytes / (1 << 20), read_seconds, build_seconds,
                static_cast<double>(args.rays) / trace_seconds, local_seconds, reduce_seconds,
                100.0 * static_cast<double>(found) / static_cast<double>(args.rays));
  }
  return 0;
}

int run(int argc, char** argv, MPI_Comm comm) {
  CLI::App app{"sphray-mpi: render with the spheres spread over MPI ranks", "sphray-mpi"};
  app.require_subcommand(1, 1);
  RenderArgs render_args;
  CLI::App* render = app.add_subcommand("render", "Render a scene; rank 0 writes the image");
  // A time limit would differ between the ranks' clocks; the tree is always built. Threads
  // serve the replicated distribution (0: the node's cores shared among its ranks); split
  // ranks trace their tiles in order.
  add_render_options(
      *render, render_args,
      {.threads = true, .time_limit = false, .accel = false, .force = true, .precision = false});
  std::string distribution_name = "auto";
  render
      ->add_option("--distribution", distribution_name,
                   "replicated: every rank holds the whole scene and renders a share of the "
                   "tiles; split: the spheres are split between the ranks, which answer every "
                   "ray together; routed: split, every rank renders the tiles its region meets "
                   "first and sends each ray only to the ranks whose region it crosses; "
                   "auto: replicated when the scene fits every rank, split otherwise")
      ->check(CLI::IsMember({"auto", "replicated", "split", "routed"}))
      ->capture_default_str();
  std::string generate_scene, generate_output;
  bool generate_force = false;
  CLI::App* generate =
      app.add_subcommand("generate", "Write a scene's spheres (e.g. random:N) as a particle file");
  generate->add_option("scene", generate_scene, "A preset (random:N) or a .json scene")->required();
  generate->add_option("-o,--output", generate_output, "The particle file to write")->required();
  generate->add_flag("--force,-f", generate_force, "Replace the output even if it is read-only");
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
  bench->add_flag("--routed", bench_args.routed,
                  "Each rank traces its share of every batch, sent only to the ranks whose "
                  "region a ray crosses (intersect_routed); prints the routed table's row");
  bench->add_option("--from", bench_args.from, "The axis the view looks along, from its + side")
      ->check(CLI::IsMember({"x", "y", "z"}))
      ->capture_default_str();
  bench->add_flag("--beside", bench_args.beside,
                  "Aim every ray beside the spheres: the cost of a tree's root alone");
  // Every rank parses its own arguments (an MPMD launch gives each its own): the ranks agree on
  // the outcome and on the subcommand before any of them starts one.
  enum Command : std::uint64_t { kHelp = 0, kRender = 1, kGenerate = 2, kBench = 3 };
  RankError parsed;
  std::uint64_t command = kHelp;
  int help_status = 0;
  try {
    app.parse(argc, argv);
    command = *render ? kRender : *generate ? kGenerate : kBench;
  } catch (const CLI::Success& e) {
    if (rank_of(comm) == 0) help_status = app.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::string message = e.what();
    parsed = {kExitUsage, message.substr(0, message.find('\n')) + " (see sphray-mpi --help)"};
  }
  if (const int status = agreed_status(parsed, comm)) return status;
  const Setting which[] = {{"the subcommand (or --help)", command, false}};
  if (const int status = refuse_disagreement(which, comm)) return status;
  switch (command) {
    case kRender:
      return run_render(render_args,
                        distribution_name == "replicated" ? Distribution::replicated
                        : distribution_name == "split"    ? Distribution::split
                        : distribution_name == "routed"   ? Distribution::routed
                                                          : Distribution::automatic,
                        comm);
    case kGenerate:
      return run_generate(generate_scene, generate_output, generate_force, comm);
    case kBench:
      return run_bench(bench_args, comm);
    default:
      return help_status;
  }
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  // A named temporary output (file systems without O_TMPFILE) is removed on a fatal signal, as
  // `sphray render` does; installed after MPI_Init, whose own handlers are left as they are.
  remove_temporaries_on_signals();
  int status = kExitIo;
  try {
    status = run(argc, argv, MPI_COMM_WORLD);
  } catch (const std::exception& e) {
    // Unexpected, and perhaps on one rank alone, in the middle of the collectives (every error
    // that can be met before them is agreed on above): end the whole job rather than leave the
    // others waiting in a reduction.
    std::fprintf(stderr, "sphray-mpi: rank %d: %s\n", rank_of(MPI_COMM_WORLD), e.what());
    MPI_Abort(MPI_COMM_WORLD, kExitIo);
  }
  MPI_Finalize();
  return status;
}
