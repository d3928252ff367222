#include "sphray/render/path_tracer.hpp"

#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "frame/scene_queries.hpp"
#include "frame/tile_tasks.hpp"
#include "path/wavefront.hpp"
#include "sphray/render/camera.hpp"

namespace sphray::render {
namespace {

using Clock = std::chrono::steady_clock;

constexpr std::size_t kTilePixels = kTileSize * kTileSize;
constexpr int kMaxDepth = 10000;
constexpr int kMaxSpp = 65536;

struct Tile {
  int x0, y0, width, height;
  std::size_t pixels() const {
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
};

Tile tile_at(std::size_t index, int image_width, int image_height) {
  const TileRect rect = tile_rect(index, image_width, image_height);
  return {rect.x0, rect.y0, rect.width, rect.height};
}

void check(const RenderOptions& o) {
  if (o.width < 1 || o.width > kMaxImageSide || o.height < 1 || o.height > kMaxImageSide) {
    throw std::invalid_argument("image size: expected 1 to " + std::to_string(kMaxImageSide) +
                                " pixels a side");
  }
  if (o.spp < 1 || o.spp > kMaxSpp) {
    throw std::invalid_argument("spp: expected 1 to " + std::to_string(kMaxSpp));
  }
  if (o.threads < 0 || o.threads > 1024) {
    throw std::invalid_argument("threads: expected 0 (all) to 1024");
  }
  o.share.check(tile_count(o.width, o.height));
  if (o.max_depth < 1 || o.max_depth > kMaxDepth) {
    throw std::invalid_argument("max depth: expected 1 to " + std::to_string(kMaxDepth));
  }
  if (!(o.time_limit >= 0.0) || !std::isfinite(o.time_limit)) {
    throw std::invalid_argument("time limit: expected a number of seconds >= 0 (0: none)");
  }
}

// What the tiles add up while they run: rays by kind, and thread time in and out of the kernel.
struct Counters {
  std::atomic<std::uint64_t> camera{0}, bounce{0};
  std::atomic<std::int64_t> kernel_ns{0}, trace_ns{0};
  std::atomic<std::size_t> tiles_done{0};

  RayCounts rays() const { return {camera.load(), bounce.load(), 0}; }
};

// Called with each wavefront the kernel traced, and its round (0: the first stream call). A
// tracer given one sample at a time starts every path in round 0: the round is the bounce.
using Recorder = std::function<void(int round, std::span<const Ray> rays)>;

// The most samples of a tile traced in one call: its paths then number up to 256 times this, and
// their light is kept apart (12 bytes each) until they are summed in sample order.
constexpr int kSamplesPerPass = 16;
static_assert(kWavefront * kSamplesPerPass - 1 <=
                  std::numeric_limits<decltype(PathRecord::slot)>::max(),
              "a path's entry must fit PathRecord::slot");

// One tile's pass (samples [first, first + count) of its pixels) in a wavefront: where its
// paths stand between rounds.
struct TilePass {
  Tile tile{};
  std::uint32_t first = 0, count = 0;
  std::size_t paths = 0;     // the pass's paths: the tile's pixels times count
  std::size_t next = 0;      // the next path to start
  std::size_t bouncing = 0;  // the round's paths that were live before it: lanes [0, bouncing)
  std::uint64_t rays = 0;    // traced so far
  int round = 0;
};

// Traces samples [first, first + count) of every pixel of one tile, all of their paths through
// one wavefront: per round one stream call over the live paths, then each hit adds sky light or
// scatters. A path's light goes to its own entry (sample, pixel) and the entries are summed in
// sample order at the end, so a pixel's sum has the same bits as one sample at a time. Paths
// that end leave their lanes to the next samples' paths: the wavefront stays full until the
// last paths start. Fixed-size buffers for the rays, and the thread's own for the light's
// entries. The rounds are steps of their own (begin, start_round, end_round, end) for a caller
// that advances several tiles together (TileGroup).
class TileTracer {
 public:
  TileTracer(const Scene& scene, const Camera& camera, const RayQueries& queries,
             const RenderOptions& options)
      : scene_(scene),
        camera_(camera),
        queries_(queries),
        options_(options),
        table_(scene),
        passes_(clone_for(active_isa())),
        seed_hash_(PathRandom::seed_hash(options.seed)) {}

  void trace(const Tile& tile, std::uint32_t first, std::uint32_t count, Vec3* sums,
             Counters& counters, const Recorder* recorder) const {
    const auto tile_start = Clock::now();
    // The thread's wavefront, zeroed when made: the passes also run over the lanes just past the
    // live ones (Wavefront's lane rules), which so always hold defined values. (Nothing a tile
    // calls runs another tile's task on this thread: the kernel's queries start no tasks.)
    thread_local const std::unique_ptr<Wavefront> wavefront = std::make_unique<Wavefront>();
    Wavefront& w = *wavefront;
    // A path's entry is zeroed when it starts (start_paths), so the thread's buffer, allocated
    // once, is taken as it is.
    thread_local std::vector<Vec3> entries;
    if (entries.empty()) entries.resize(kPassEntries);
    Vec3* const radiance = entries.data();
    TilePass pass = begin(tile, first, count, w);
    std::int64_t kernel_ns = 0;
    while (start_round(pass, radiance, w)) {
      const auto kernel_start = Clock::now();
      // The new paths' camera rays in a call of their own: the kernel looks for coherent groups
      // of rays from a call's start, and camera rays from neighbouring pixels are (bvh packets).
      intersect(w, 0, pass.bouncing);
      intersect(w, pass.bouncing, w.live);
      kernel_ns +=
          std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - kernel_start).count();
      end_round(pass, radiance, w, recorder);
    }
    end(pass, radiance, sums, counters);
    counters.kernel_ns += kernel_ns;
    counters.trace_ns +=
        std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - tile_start).count();
  }

  // The entries a pass's light needs at most: a tile's pixels times kSamplesPerPass.
  static constexpr std::size_t kPassEntries = kWavefront * kSamplesPerPass;

  TilePass begin(const Tile& tile, std::uint32_t first, std::uint32_t count, Wavefront& w) const {
    w.live = 0;
    return {tile, first, count, tile.pixels() * count};
  }

  // Starts the round's new paths behind the live ones; false when the pass has none left.
  bool start_round(TilePass& pass, Vec3* radiance, Wavefront& w) const {
    pass.bouncing = w.live;
    start_paths(pass.tile, pass.first, pass.paths, pass.next, radiance, w);
    return w.live > 0;
  }

  // Ends the round, the live paths' hits known: shades them.
  void end_round(TilePass& pass, Vec3* radiance, Wavefront& w, const Recorder* recorder) const {
    if (recorder != nullptr) (*recorder)(pass.round, std::span(w.rays.data(), w.live));
    pass.rays += w.live;
    ++pass.round;
    passes_.shade(w, table_, scene_.sky, radiance);
  }

  // Adds the ended pass's light to the tile's sums, in sample order, and counts its rays.
  void end(const TilePass& pass, const Vec3* radiance, Vec3* sums, Counters& counters) const {
    const std::size_t pixels = pass.tile.pixels();
    for (std::size_t sample = 0; sample < pass.count; ++sample) {
      for (std::size_t i = 0; i < pixels; ++i)
        sums[i] += radiance[sample * pixels + i];
    }
    counters.camera += pass.paths;
    counters.bounce += pass.rays - pass.paths;
  }

 private:
  void intersect(Wavefront& w, std::size_t begin, std::size_t end) const {
    if (begin == end) return;
    queries_.intersect(std::span(w.rays.data() + begin, end - begin),
                       std::span(w.hits.data() + begin, end - begin));
  }

  // Starts paths next, next + 1, ... in the lanes behind the live paths, in whole groups of 32
  // lanes (the kernel's coherent group) while more than that are left to start. Here each lane's
  // path state (throughput, rays left and entry, zeroed: only a path that misses writes its light
  // there) and camera sample (pixel, sample, the pixel's corner); the passes' start() draws the
  // camera rays, all lanes together.
  void start_paths(const Tile& tile, std::uint32_t first, std::size_t paths, std::size_t& next,
                   Vec3* radiance, Wavefront& w) const {
    constexpr std::size_t kGroup = 32;
    const std::size_t begin = w.live;
    const std::size_t free = kWavefront - begin;
    const std::size_t starts = std::min(paths - next, free - free % kGroup);
    const std::size_t end = begin + starts;
    const std::int32_t max_depth = options_.max_depth;
    for (std::size_t i = begin; i < end; ++i) {
      w.path.throughput_r[i] = w.path.throughput_g[i] = w.path.throughput_b[i] = 1.0f;
      w.path.rays_left[i] = max_depth;
      w.path.slot[i] = static_cast<std::uint32_t>(next + (i - begin));
    }
    if (tile.width == kTileSize && tile.height == kTileSize) {  // sides known: shifts and masks
      constexpr std::integral_constant<std::size_t, kTileSize> side;
      place(tile, side, side, first, next, begin, end, w);
    } else {
      place(tile, static_cast<std::size_t>(tile.width), static_cast<std::size_t>(tile.height),
            first, next, begin, end, w);
    }
    std::fill_n(radiance + next, starts, Vec3{0.0f, 0.0f, 0.0f});
    next += starts;
    w.live = end;
    if (starts > 0) passes_.start(w, begin, camera_, seed_hash_);
  }

  // The pixels and samples of the paths path, path + 1, ... in lanes [begin, end): path p is
  // sample first + p / pixels of the tile's pixel p % pixels, in row order (its entry is p).
  // Without a cursor carried from lane to lane, in 32-bit integers (an image has at most 2^28
  // pixels, a tile's pass 2^16 paths): the loop vectorises.
  template <class Side>
  void place(const Tile& tile, Side width, Side height, std::uint32_t first, std::size_t path,
             std::size_t begin, std::size_t end, Wavefront& w) const {
    static_assert(std::uint64_t{kMaxImageSide} * kMaxImageSide <= 0xffffffffu);
    const std::uint32_t pixels = static_cast<std::uint32_t>(width * height);
    const auto image_width = static_cast<std::uint32_t>(options_.width);
    const auto x0 = static_cast<std::uint32_t>(tile.x0), y0 = static_cast<std::uint32_t>(tile.y0);
    const auto path0 = static_cast<std::uint32_t>(path - begin);
    for (std::size_t i = begin; i < end; ++i) {
      const std::uint32_t p = path0 + static_cast<std::uint32_t>(i), pixel = p % pixels;
      const std::uint32_t x = x0 + pixel % static_cast<std::uint32_t>(width);
      const std::uint32_t y = y0 + pixel / static_cast<std::uint32_t>(width);
      w.camera.pixel[i] = y * image_width + x;  // the pixel's index in the image
      w.camera.sample[i] = first + p / pixels;
      w.camera.x[i] = static_cast<float>(static_cast<std::int32_t>(x));
      w.camera.y[i] = static_cast<float>(static_cast<std::int32_t>(y));
    }
  }

  const Scene& scene_;
  const Camera& camera_;
  const RayQueries& queries_;
  const RenderOptions& options_;
  ShadingTable table_;
  const ShadeClone& passes_;  // the passes' copy for the widest vectors the queries use
  std::uint64_t seed_hash_;
};

// Collective queries: a process's tiles traced kGroupTiles at a time, each in a wavefront of its
// own, all of their live paths in one call a round. A process then makes as many calls as its
// group has rounds, whatever the number of its tiles, and each call is a batch large enough
// for the exchanges between processes to pay. A tile's paths get the same rays and hits as
// traced alone, so the image is the same bit for bit.
class TileGroup {
 public:
  explicit TileGroup(std::size_t tiles) : slots_(std::min(tiles, kGroupTiles)) {
    for (Slot& slot : slots_)
      slot.entries.resize(TileTracer::kPassEntries);
    rays_.resize(slots_.size() * kWavefront);
    hits_.resize(slots_.size() * kWavefront);
  }

  // Traces samples [first, first + count) of the tiles of options.share, adding tile t's light
  // to sums[t * kTilePixels, ...); done() as each tile's pass ends.
  template <class Done>
  void trace(const TileTracer& tracer, const RayQueries& queries, const RenderOptions& options,
             std::uint32_t first, std::uint32_t count, Vec3* sums, Counters& counters,
             Done&& done) {
    const std::size_t tiles = options.share.size(tile_count(options.width, options.height));
    const auto start = Clock::now();
    std::int64_t kernel_ns = 0;
    std::size_t next = 0;  // the next tile to begin
    for (;;) {
      std::size_t live = 0;
      for (Slot& slot : slots_) {
        // A slot whose pass has ended takes the next tile, until none is left.
        while (!slot.busy || !tracer.start_round(slot.pass, slot.entries.data(), *slot.w)) {
          if (slot.busy) {
            tracer.end(slot.pass, slot.entries.data(), sums + slot.tile * kTilePixels, counters);
            slot.busy = false;
            done();
          }
          if (next == tiles) break;
          slot.tile = options.share.tile(next++);
          slot.pass = tracer.begin(tile_at(slot.tile, options.width, options.height), first, count,
                                   *slot.w);
          slot.busy = true;
        }
        if (slot.busy) {
          std::copy_n(slot.w->rays.data(), slot.w->live, rays_.data() + live);
          live += slot.w->live;
        }
      }
      if (live == 0) break;
      const auto kernel_start = Clock::now();
      queries.intersect(std::span(rays_.data(), live), std::span(hits_.data(), live));
      kernel_ns +=
          std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - kernel_start).count();
      live = 0;
      for (Slot& slot : slots_) {
        if (!slot.busy) continue;
        std::copy_n(hits_.data() + live, slot.w->live, slot.w->hits.data());
        live += slot.w->live;
        tracer.end_round(slot.pass, slot.entries.data(), *slot.w, nullptr);
      }
    }
    counters.kernel_ns += kernel_ns;
    counters.trace_ns +=
        std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - start).count();
  }

 private:
  struct Slot {
    std::unique_ptr<Wavefront> w = std::make_unique<Wavefront>();  // zeroed, as a thread's
    std::vector<Vec3> entries;
    TilePass pass;
    std::size_t tile = 0;
    bool busy = false;
  };
  std::vector<Slot> slots_;
  std::vector<Ray> rays_;  // the group's live rays, slot after slot
  std::vector<Hit> hits_;
};

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// How many samples the next pass traces, done of spp having taken elapsed seconds: up to
// kSamplesPerPass at once; under a time limit one first, then as many as the time left allows
// at the rate so far (at least one), so that a pass ends about when the time is up.
int samples_in_next_pass(int done, int spp, double elapsed, double time_limit) {
  const int most = std::min(kSamplesPerPass, spp - done);
  if (time_limit <= 0.0) return most;
  if (done == 0) return 1;
  const double fit = (time_limit - elapsed) * static_cast<double>(done) / elapsed;
  return std::clamp(static_cast<int>(std::min(fit, double{kSamplesPerPass})), 1, most);
}

}  // namespace

std::vector<Vec3> render_radiance(const Scene& scene, const RenderOptions& options,
                                  const Progress& progress, RenderStats* stats) {
  check(options);
  const auto build_start = Clock::now();
  const SceneQueries queries(scene.spheres, options.accel, options.threads);
  const double build_seconds = seconds_since(build_start);
  std::vector<Vec3> image = render_radiance(scene, queries, options, progress, stats);
  if (stats != nullptr) {
    stats->build_seconds = queries.uses_bvh() ? build_seconds : 0.0;
    stats->bvh = queries.uses_bvh();
  }
  return image;
}

std::vector<Vec3> render_radiance(const Scene& scene, const RayQueries& queries,
                                  const RenderOptions& options, const Progress& progress,
                                  RenderStats* stats) {
  check(options);
  if (queries.collective() && options.time_limit > 0.0) {
    throw std::invalid_argument(
        "time limit: not with queries shared between processes (their clocks differ)");
  }
  check_share(queries, options);
  const Camera camera(scene.camera, options.width, options.height);
  const TileTracer tracer(scene, camera, queries, options);
  const std::size_t tiles = tile_count(options.width, options.height);
  const std::size_t mine = options.share.size(tiles);
  // Sums per tile, each tile's pixels together, so a tile's thread writes one block.
  std::vector<Vec3> sums(tiles * kTilePixels, Vec3{0, 0, 0});
  Counters counters;
  const std::size_t total = mine * static_cast<std::size_t>(options.spp);
  const auto tile_done = [&](std::uint32_t count) {
    const std::size_t done = counters.tiles_done += count;  // tiles times samples
    if (progress) progress(done, total, counters.rays());
  };
  const auto trace_tiles = [&](std::uint32_t first, std::uint32_t count, std::size_t begin,
                               std::size_t end) {
    for (std::size_t k = begin; k != end; ++k) {
      const std::size_t t = options.share.tile(k);
      tracer.trace(tile_at(t, options.width, options.height), first, count, &sums[t * kTilePixels],
                   counters, nullptr);
      tile_done(count);
    }
  };

  // Passes over every tile, each of up to kSamplesPerPass samples: a time limit is checked
  // between passes, so every pixel gets the same number of samples (at least one), and a pass
  // is never cut short.
  if (progress) progress(0, total, {});  // the tracing starts: any tree is built by now
  const auto start = Clock::now();
  int passes = 0;  // the samples traced so far
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  const std::unique_ptr<TileGroup> group =
      queries.collective() ? std::make_unique<TileGroup>(mine) : nullptr;
  while (passes < options.spp) {
    const auto first = static_cast<std::uint32_t>(passes);
    const auto count = static_cast<std::uint32_t>(
        samples_in_next_pass(passes, options.spp, seconds_since(start), options.time_limit));
    if (queries.collective()) {
      // Every process its group's calls, one a round, then finish() below.
      group->trace(tracer, queries, options, first, count, sums.data(), counters,
                   [&] { tile_done(count); });
    } else {
      trace_tiles_in(arena, mine, [&](std::size_t begin, std::size_t end) {
        trace_tiles(first, count, begin, end);
      });
    }
    passes += static_cast<int>(count);
    if (options.time_limit > 0.0 && seconds_since(start) >= options.time_limit) break;
  }
  if (queries.collective()) queries.finish();
  const double seconds = seconds_since(start);

  std::vector<Vec3> image(static_cast<std::size_t>(options.width) *
                          static_cast<std::size_t>(options.height));
  const float inverse = 1.0f / static_cast<float>(passes);
  for (std::size_t t = 0; t < tiles; ++t) {
    const Tile tile = tile_at(t, options.width, options.height);
    for (std::size_t i = 0; i < tile.pixels(); ++i) {
      const std::size_t x =
          static_cast<std::size_t>(tile.x0) + i % static_cast<std::size_t>(tile.width);
      const std::size_t y =
          static_cast<std::size_t>(tile.y0) + i / static_cast<std::size_t>(tile.width);
      image[y * static_cast<std::size_t>(options.width) + x] = sums[t * kTilePixels + i] * inverse;
    }
  }
  if (stats != nullptr) {
    stats->seconds = seconds;
    stats->build_seconds = 0.0;
    stats->bvh = false;
    stats->camera_rays = counters.camera;
    stats->bounce_rays = counters.bounce;
    stats->shadow_rays = 0;
    stats->spp = passes;
    stats->kernel_seconds = static_cast<double>(counters.kernel_ns.load()) * 1e-9;
    stats->trace_seconds = static_cast<double>(counters.trace_ns.load()) * 1e-9;
  }
  return image;
}

namespace {

// Gamma 2, as the book's linear_to_gamma: the square root of the clamped-below value.
Image encode(const RenderOptions& options, const std::vector<Vec3>& radiance) {
  Image image{options.width, options.height, std::vector<std::uint8_t>(3 * radiance.size())};
  for (std::size_t i = 0; i < radiance.size(); ++i) {
    const Vec3 c = radiance[i];
    image.rgb[3 * i + 0] = to_byte(std::sqrt(std::max(c.x, 0.0f)));
    image.rgb[3 * i + 1] = to_byte(std::sqrt(std::max(c.y, 0.0f)));
    image.rgb[3 * i + 2] = to_byte(std::sqrt(std::max(c.z, 0.0f)));
  }
  return image;
}

}  // namespace

Image render_path(const Scene& scene, const RenderOptions& options, const Progress& progress,
                  RenderStats* stats) {
  return encode(options, render_radiance(scene, options, progress, stats));
}

Image render_path(const Scene& scene, const RayQueries& queries, const RenderOptions& options,
                  const Progress& progress, RenderStats* stats) {
  return encode(options, render_radiance(scene, queries, options, progress, stats));
}

std::vector<Ray> record_path_rays(const Scene& scene, const RenderOptions& options,
                                  int first_bounce, int last_bounce) {
  check(options);
  const Camera camera(scene.camera, options.width, options.height);
  const SceneQueries queries(scene.spheres, options.accel, options.threads);
  const TileTracer tracer(scene, camera, queries, options);
  std::vector<Ray> recorded;
  const Recorder recorder = [&](int bounce, std::span<const Ray> rays) {
    if (bounce >= first_bounce && bounce <= last_bounce)
      recorded.insert(recorded.end(), rays.begin(), rays.end());
  };
  const std::size_t tiles = tile_count(options.width, options.height);
  std::array<Vec3, kTilePixels> sums{};
  Counters counters;
  // One sample per call: every path starts in round 0, so a round is the paths' bounce.
  for (int s = 0; s < options.spp; ++s) {
    for (std::size_t t = 0; t < tiles; ++t)
      tracer.trace(tile_at(t, options.width, options.height), static_cast<std::uint32_t>(s), 1,
                   sums.data(), counters, &recorder);
  }
  return recorded;
}

}  // namespace sphray::render
