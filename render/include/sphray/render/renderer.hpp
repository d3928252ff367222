// The renderer: camera rays per 16x16 tile, handed to the kernel as one stream, shaded from the
// hits. Tiles run in parallel on oneTBB; every sample's jitter comes from its pixel, sample
// index and the seed alone, so the image is the same bit for bit whatever the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sphray/render/ray_queries.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {

enum class Mode { normals, flat, depth, id, shaded, path };

/// "normals", "flat", "depth", "id", "shaded", "path", in that order.
std::vector<std::string> mode_names();
std::string_view mode_name(Mode mode);
std::optional<Mode> parse_mode(std::string_view name);

/// How the spheres are queried: a sphray::SphereBVH from a few dozen spheres on (automatic),
/// always, or never (brute force over all spheres for every ray).
enum class Accel { automatic, bvh, brute_force };

/// "auto", "bvh", "brute", in that order.
std::vector<std::string> accel_names();
std::optional<Accel> parse_accel(std::string_view name);

/// An image is traced in tiles of kTileSize x kTileSize pixels (the last column and row cut
/// short), numbered row by row from the top left.
struct TileRect {
  int x0, y0, width, height;
};
std::size_t tile_count(int width, int height);
/// Tile `tile` (below tile_count) of an image of that size.
TileRect tile_rect(std::size_t tile, int image_width, int image_height);

/// A share of an image's tiles: those t with t % count == index, interleaved so that the
/// shares of an image whose cost varies across it cost about the same; or, when `listed` holds
/// them, those tiles (strictly ascending): shares of other shapes, such as sphray-mpi's tiles
/// whose rays meet a rank's own spheres first. index and count still name the process and the
/// processes whose shares add up to the image. The whole image by default.
struct TileShare {
  int index = 0, count = 1;
  std::optional<std::vector<std::uint32_t>> listed;

  TileShare() = default;
  TileShare(int index_, int count_) : index(index_), count(count_) {}
  TileShare(int index_, int count_, std::vector<std::uint32_t> tiles)
      : index(index_), count(count_), listed(std::move(tiles)) {}

  /// How many of tiles (0 to tiles - 1) are in the share, and the k-th of them.
  std::size_t size(std::size_t tiles) const {
    if (listed) return listed->size();
    const auto i = static_cast<std::size_t>(index), n = static_cast<std::size_t>(count);
    return tiles > i ? (tiles - i - 1) / n + 1 : 0;
  }
  std::size_t tile(std::size_t k) const {
    if (listed) return (*listed)[k];
    return static_cast<std::size_t>(index) + k * static_cast<std::size_t>(count);
  }
  /// Throws std::invalid_argument unless 0 <= index < count and the listed tiles, if any, are
  /// strictly ascending and below tiles.
  void check(std::size_t tiles) const;
};

struct RenderOptions {
  Mode mode = Mode::normals;
  int width = 400, height = 225;
  int spp = 1;             // samples per pixel; 1 samples each pixel's centre, more are jittered
  std::uint64_t seed = 0;  // the jitter's seed
  int threads = 0;         // 0: as many as oneTBB offers
  Accel accel = Accel::automatic;
  int max_depth = 50;       // path mode: rays per path at most, the camera's included (the book's)
  double time_limit = 0.0;  // path mode: seconds after which no sample is started (0: none)
  // Only these tiles are rendered, the other pixels left 0 (black): the shares of processes
  // that each hold the whole scene add up to the image, byte for byte (sphray-mpi).
  TileShare share;
  // What the geometry is traced in: float64 takes the scene's doubles (Scene::doubles, or its
  // floats widened), for every mode but path (docs/double.md, "The command").
  Precision precision = Precision::float32;
};

/// 8-bit RGB, rows top to bottom, no padding.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};

struct RenderStats {
  double seconds = 0;             // wall time of the tiles, scene and output excluded
  double build_seconds = 0;       // building the BVH (before the tiles), 0 without one
  bool bvh = false;               // whether a BVH answered the queries
  std::uint64_t camera_rays = 0;  // width * height * spp
  std::uint64_t shadow_rays = 0;  // occlusion queries (shaded mode)
  std::uint64_t bounce_rays = 0;  // path mode: rays after the camera's
  int spp = 0;                    // samples every pixel got (path mode: fewer on a time limit)
  double kernel_seconds = 0;      // path mode: thread time in the kernel's stream calls
  double trace_seconds = 0;       // path mode: thread time in the tiles, kernel included
};

/// Rays traced so far, by kind.
struct RayCounts {
  std::uint64_t camera = 0, bounce = 0, shadow = 0;
};

/// Called once with done 0 when the tracing starts (after any tree is built), then from worker
/// threads after each tile with the tiles finished so far, the total (path mode: tiles times
/// samples) and the rays traced so far.
using Progress = std::function<void(std::size_t done, std::size_t total, const RayCounts& rays)>;

inline constexpr int kTileSize = 16;

/// Renders scene (its camera, the size in options). Throws SceneError if the camera cannot be
/// placed, std::invalid_argument for a size, spp or thread count out of range.
Image render(const Scene& scene, const RenderOptions& options, const Progress& progress = {},
             RenderStats* stats = nullptr);

/// The same image, the spheres' hits answered by queries instead of the renderer's own (which
/// must give the same answers for scene.spheres: the image is then the same bit for bit).
/// options.accel is not used; stats report no tree. Collective queries (ray_queries.hpp) with
/// a share of the tiles must take uneven calls, else std::invalid_argument.
Image render(const Scene& scene, const RayQueries& queries, const RenderOptions& options,
             const Progress& progress = {}, RenderStats* stats = nullptr);

/// The shading of one ray's hit, exposed for tests and for embedding in other loops.
Vec3 sky(const Ray& ray);
/// A colour component in [0,1] to a byte as the book writes it: int(255.999 * c), clamped.
std::uint8_t to_byte(float c);

}  // namespace sphray::render
