#include "sphray/render/renderer.hpp"

#include "sphray/render/material.hpp"

#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "frame/scene_queries.hpp"
#include "frame/tile_tasks.hpp"
#include "sphray/render/camera.hpp"
#include "sphray/render/path_tracer.hpp"

namespace sphray::render {
namespace {

constexpr std::array<std::string_view, 6> kModeNames = {"normals", "flat",   "depth",
                                                        "id",      "shaded", "path"};
constexpr int kMaxSpp = 65536;
constexpr int kMaxThreads = 1024;
constexpr std::size_t kTilePixels = kTileSize * kTileSize;

// Where the sun is in shaded mode: above, to the right and in front of the usual cameras.
const Vec3 kLight = normalize(Vec3{0.6f, 1.0f, 0.45f});
constexpr float kAmbient = 0.15f;

// SplitMix64's finaliser (the path tracer's, material.hpp): a well-mixed 64-bit value from any
// counter.
std::uint64_t mix(std::uint64_t z) {
  return PathRandom::mix(z);
}

// The offset of sample s of pixel p inside the pixel, from (p, s, seed) alone, so no thread
// or tile order can change it. One sample per pixel goes through the centre.
std::array<float, 2> jitter(std::uint64_t pixel, int spp, int s, std::uint64_t seed) {
  if (spp == 1) return {0.5f, 0.5f};
  std::uint64_t counter = pixel * static_cast<std::uint64_t>(spp) + static_cast<std::uint64_t>(s);
  std::uint64_t bits = mix(seed * 0x9e3779b97f4a7c15ull + mix(counter + 1));
  return {static_cast<float>(bits >> 40) * 0x1p-24f,
          static_cast<float>((bits >> 16) & 0xffffffu) * 0x1p-24f};
}

Vec3 id_color(std::uint32_t id) {
  std::uint64_t h = mix(std::uint64_t{id} + 1);  // mix(0) is 0: start ids at 1
  auto channel = [h](int shift) {
    return 0.2f + 0.8f * static_cast<float>((h >> shift) & 0xffu) / 255.0f;
  };
  return {channel(0), channel(8), channel(16)};
}

// ray in float, for what only needs its direction roughly (the sky's colour).
template <Scalar S>
Ray as_float(const BasicRay<S>& ray) {
  return {vec3_cast<float>(ray.origin), vec3_cast<float>(ray.dir)};
}

// Shades one ray's hit in the chosen mode: arithmetic on the hit and its surface, and in
// shaded mode whether the hit sees the light (its shadow ray, traced by the caller). The
// geometry is in S, the colours in float.
template <Scalar S>
class Shader {
 public:
  using RayS = BasicRay<S>;
  using HitS = BasicHit<S>;

  // depth_scale: the camera's distance to what it looks at. Depth: grey = D / (D + distance),
  // so the point of interest is mid-grey whatever the scene's scale.
  Shader(const Scene& scene, BasicSphereView<S> view, Mode mode, float depth_scale)
      : scene_(scene), view_(view), mode_(mode), depth_scale_(depth_scale) {}

  bool casts_shadows() const { return mode_ == Mode::shaded; }

  // Shaded mode: the ray from the hit towards the light, or none where the surface faces away
  // from it (or the ray missed).
  std::optional<RayS> shadow_ray(const RayS& ray, const HitS& hit) const {
    if (!hit.found()) return std::nullopt;
    const BasicSurface<S> s = surface(view_, ray, hit);
    const BasicVec3<S> normal = s.front_face ? s.normal : -s.normal;
    const BasicVec3<S> light = vec3_cast<S>(kLight);
    if (!(dot(normal, light) > S(0))) return std::nullopt;
    if constexpr (std::is_same_v<S, double>) {
      // Double scenes are where a relative offset fails (1e-4 of 3e4 is 3 m): the kernel's
      // spawn() leaves the surface by its error bound instead.
      return spawn(s, light);
    } else {
      // Float keeps the book's relative offset (its images stay the same bit for bit): start
      // the shadow ray a little off the surface, relative to the point's magnitude, so rounding
      // cannot put it back inside the sphere it leaves.
      const Vec3 p = s.point;
      const float scale = std::max({1.0f, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
      return Ray{p + (1e-4f * scale) * normal, kLight};
    }
  }

  // lit: shaded mode, whether the hit's shadow ray reached the light.
  Vec3 shade(const RayS& ray, const HitS& hit, bool lit) const {
    if (!hit.found())
      return mode_ == Mode::depth || mode_ == Mode::id ? Vec3{0, 0, 0} : sky(as_float(ray));
    switch (mode_) {
      case Mode::normals:
        return 0.5f * (vec3_cast<float>(surface(view_, ray, hit).normal) + Vec3{1, 1, 1});
      case Mode::flat:
        return color_of(scene_, hit.id);  // unshaded; grey without colours
      case Mode::depth: {
        float grey = depth_scale_ / (depth_scale_ + static_cast<float>(hit.t * length(ray.dir)));
        return {grey, grey, grey};
      }
      case Mode::id:
        return id_color(hit.id);
      case Mode::shaded:
        return diffuse(ray, hit, lit);
      case Mode::path:
        break;  // render_path
    }
    return {0, 0, 0};
  }

  // The output byte of an averaged colour; shaded mode is gamma-2 encoded as in the book.
  float encode(float c) const { return mode_ == Mode::shaded ? std::sqrt(std::max(c, 0.0f)) : c; }

 private:
  Vec3 diffuse(const RayS& ray, const HitS& hit, bool lit) const {
    const BasicSurface<S> s = surface(view_, ray, hit);
    const Vec3 normal = vec3_cast<float>(s.front_face ? s.normal : -s.normal);
    const Vec3 albedo = color_of(scene_, hit.id);  // grey without colours
    const float light = lit ? dot(normal, kLight) : 0.0f;
    return (kAmbient + (1.0f - kAmbient) * light) * albedo;
  }

  const Scene& scene_;
  BasicSphereView<S> view_;
  Mode mode_;
  float depth_scale_;
};

// Calls visit(i, x, y) for the pixels of rects in turn, each rect row by row, i from 0.
template <class Visit>
void for_each_pixel(std::span<const TileRect> rects, Visit&& visit) {
  std::size_t i = 0;
  for (const TileRect& r : rects) {
    for (int k = 0; k < r.width * r.height; ++k)
      visit(i++, r.x0 + k % r.width, r.y0 + k / r.width);
  }
}

std::size_t pixels_in(std::span<const TileRect> rects) {
  std::size_t n = 0;
  for (const TileRect& r : rects)
    n += static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height);
  return n;
}

// Scratch for tracing the pixels of some rects: one entry per pixel in each span.
template <Scalar S>
struct PixelScratch {
  std::span<BasicRay<S>> rays;
  std::span<BasicHit<S>> hits;
  std::span<Vec3> sum;
  std::span<bool> lit;
  std::span<BasicRay<S>> shadows;
  std::span<std::uint32_t> owner;  // the hit each shadow ray starts from
  std::span<bool> blocked;
};

// The scratch of one tile, on the stack: no allocation.
template <Scalar S>
struct TileScratch {
  std::array<BasicRay<S>, kTilePixels> rays, shadows;
  std::array<BasicHit<S>, kTilePixels> hits;
  std::array<Vec3, kTilePixels> sum;
  std::array<bool, kTilePixels> lit, blocked;
  std::array<std::uint32_t, kTilePixels> owner;
  PixelScratch<S> spans() { return {rays, hits, sum, lit, shadows, owner, blocked}; }
};

// The scratch of many tiles, on the heap.
template <Scalar S>
struct ShareScratch {
  explicit ShareScratch(std::size_t n)
      : rays(n),
        shadows(n),
        hits(n),
        sum(n),
        owner(n),
        lit(new bool[n]),
        blocked(new bool[n]),
        n(n) {}
  std::vector<BasicRay<S>> rays, shadows;
  std::vector<BasicHit<S>> hits;
  std::vector<Vec3> sum;
  std::vector<std::uint32_t> owner;
  std::unique_ptr<bool[]> lit, blocked;  // not std::vector<bool>: spans of bool
  std::size_t n;
  PixelScratch<S> spans() {
    return {rays, hits, sum, {lit.get(), n}, shadows, owner, {blocked.get(), n}};
  }
};

// Shaded mode: the shadow rays of a batch of hits, traced as one batch; lit[i] says whether
// hit i sees the light. Returns the number of shadow rays. Queries: RayQueries in float,
// SphereQueries<double> in double.
template <Scalar S, class Queries>
std::uint64_t trace_shadows(const Shader<S>& shader, const Queries& queries, std::size_t n,
                            const PixelScratch<S>& scratch) {
  std::size_t m = 0;
  for (std::size_t i = 0; i < n; ++i) {
    scratch.lit[i] = false;
    if (const auto shadow = shader.shadow_ray(scratch.rays[i], scratch.hits[i])) {
      scratch.shadows[m] = *shadow;
      scratch.owner[m] = static_cast<std::uint32_t>(i);
      ++m;
    }
  }
  queries.occluded(std::span<const BasicRay<S>>(scratch.shadows.data(), m),
                   scratch.blocked.first(m));
  for (std::size_t k = 0; k < m; ++k)
    scratch.lit[scratch.owner[k]] = !scratch.blocked[k];
  return m;
}

// Renders the pixels of rects into image: per sample, their camera rays go to the kernel as
// one stream (in shaded mode, then their shadow rays as another), then each hit is shaded and
// summed. One tile's rects trace from the stack; a collective frame traces a group of a
// process's tiles together, one call a sample. Returns the shadow rays traced.
template <Scalar S, class Queries>
std::uint64_t render_rects(std::span<const TileRect> rects, const BasicCamera<S>& camera,
                           const Queries& queries, const Shader<S>& shader,
                           const RenderOptions& options, const PixelScratch<S>& scratch,
                           Image& image) {
  const std::size_t n = pixels_in(rects);
  std::fill(scratch.sum.begin(), scratch.sum.begin() + static_cast<std::ptrdiff_t>(n), Vec3{});
  std::fill(scratch.lit.begin(), scratch.lit.begin() + static_cast<std::ptrdiff_t>(n), false);
  const std::span<const BasicRay<S>> rays(scratch.rays.data(), n);
  const std::span<const BasicHit<S>> hits(scratch.hits.data(), n);
  std::uint64_t shadow_rays = 0;
  for (int s = 0; s < options.spp; ++s) {
    for_each_pixel(rects, [&](std::size_t i, int x, int y) {
      std::uint64_t pixel =
          static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(image.width) +
          static_cast<std::uint64_t>(x);
      auto [jx, jy] = jitter(pixel, options.spp, s, options.seed);
      scratch.rays[i] = camera.ray(static_cast<float>(x) + jx, static_cast<float>(y) + jy);
    });
    queries.intersect(rays, scratch.hits.first(n));
    if (shader.casts_shadows()) shadow_rays += trace_shadows<S>(shader, queries, n, scratch);
    for (std::size_t i = 0; i < n; ++i)
      scratch.sum[i] += shader.shade(rays[i], hits[i], scratch.lit[i]);
  }
  float inverse_spp = 1.0f / static_cast<float>(options.spp);
  for_each_pixel(rects, [&](std::size_t i, int x, int y) {
    std::size_t pixel = static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                        static_cast<std::size_t>(x);
    std::uint8_t* out = &image.rgb[3 * pixel];
    Vec3 c = scratch.sum[i] * inverse_spp;
    out[0] = to_byte(shader.encode(c.x));
    out[1] = to_byte(shader.encode(c.y));
    out[2] = to_byte(shader.encode(c.z));
  });
  return shadow_rays;
}

// The tiles of one image, in parallel (or in order for collective queries), with progress and
// stats: the frame of every mode but path, in either precision.
template <Scalar S, class Queries>
Image trace_frame(const BasicCamera<S>& camera, const Queries& queries, const Shader<S>& shader,
                  bool collective, const RenderOptions& options, const Progress& progress,
                  RenderStats* stats) {
  Image image{options.width, options.height,
              std::vector<std::uint8_t>(3 * static_cast<std::size_t>(options.width) *
                                        static_cast<std::size_t>(options.height))};
  std::size_t tiles_across = (static_cast<std::size_t>(options.width) + kTileSize - 1) / kTileSize;
  std::size_t tiles_down = (static_cast<std::size_t>(options.height) + kTileSize - 1) / kTileSize;
  std::size_t tiles = options.share.size(tiles_across * tiles_down);
  std::atomic<std::size_t> done{0};
  std::atomic<std::uint64_t> shadow_rays{0};
  std::atomic<std::uint64_t> camera_rays{0};
  auto render_tiles = [&](std::size_t begin, std::size_t end) {
    TileScratch<S> scratch;
    for (std::size_t k = begin; k != end; ++k) {
      TileRect rect = tile_rect(options.share.tile(k), options.width, options.height);
      shadow_rays += render_rects(std::span<const TileRect>(&rect, 1), camera, queries, shader,
                                  options, scratch.spans(), image);
      std::size_t finished = ++done;
      camera_rays += static_cast<std::uint64_t>(rect.width) *
                     static_cast<std::uint64_t>(rect.height) *
                     static_cast<std::uint64_t>(options.spp);
      if (progress) progress(finished, tiles, {camera_rays, 0, shadow_rays});
    }
  };

  if (progress) progress(0, tiles, {});  // the tracing starts: any tree is built by now
  auto start = std::chrono::steady_clock::now();
  if (collective) {
    // The share's tiles kGroupTiles at a time, one call a sample for each group (and one for
    // its shadow rays). Processes with shares of other sizes make other numbers of calls: the
    // queries take uneven calls (checked by render()), and the frame ends with finish().
    std::vector<TileRect> rects;
    for (std::size_t k = 0; k < tiles; ++k)
      rects.push_back(tile_rect(options.share.tile(k), options.width, options.height));
    ShareScratch<S> scratch(std::min(tiles, kGroupTiles) * kTilePixels);
    for (std::size_t begin = 0; begin < tiles; begin += kGroupTiles) {
      const auto group =
          std::span<const TileRect>(rects).subspan(begin, std::min(kGroupTiles, tiles - begin));
      shadow_rays += render_rects(group, camera, queries, shader, options, scratch.spans(), image);
      camera_rays += pixels_in(group) * static_cast<std::uint64_t>(options.spp);
      done += group.size();
      if (progress) progress(done, tiles, {camera_rays, 0, shadow_rays});
    }
  } else {
    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    trace_tiles_in(arena, tiles, render_tiles);
  }
  auto seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (stats != nullptr) {
    stats->seconds = seconds;
    stats->build_seconds = 0.0;
    stats->bvh = false;
    stats->camera_rays = camera_rays;
    stats->shadow_rays = shadow_rays;
    stats->spp = options.spp;
  }
  return image;
}

// The camera's distance to what it looks at, depth mode's scale.
template <Scalar S>
float depth_scale(BasicVec3<S> lookfrom, BasicVec3<S> lookat) {
  return static_cast<float>(length(lookfrom - lookat));
}

// The frame in double (Precision::float64): the scene's doubles (or its floats widened),
// their own tree or brute force, a camera in double.
Image render_in_double(const Scene& scene, const RenderOptions& options, const Progress& progress,
                       RenderStats* stats) {
  if (options.mode == Mode::path) {
    throw std::invalid_argument(
        "precision double: expected one of the modes normals, flat, depth, id, shaded (path "
        "mode traces in float)");
  }
  std::optional<SceneDoubles> widened;
  if (!scene.doubles) widened = doubles_of(scene);
  const SceneDoubles& doubles = scene.doubles ? *scene.doubles : *widened;
  const Camerad camera(scene.camera, doubles.lookfrom, doubles.lookat, options.width,
                       options.height);
  auto build_start = std::chrono::steady_clock::now();
  const SphereQueries<double> queries(doubles.spheres.view(), options.accel, options.threads);
  auto build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - build_start).count();
  const Shader<double> shader(scene, doubles.spheres.view(), options.mode,
                              depth_scale(doubles.lookfrom, doubles.lookat));
  Image image = trace_frame(camera, queries, shader, false, options, progress, stats);
  if (stats != nullptr) {
    stats->build_seconds = queries.uses_bvh() ? build_seconds : 0.0;
    stats->bvh = queries.uses_bvh();
  }
  return image;
}

void check_options(const RenderOptions& o) {
  if (o.width < 1 || o.width > kMaxImageSide || o.height < 1 || o.height > kMaxImageSide) {
    throw std::invalid_argument("image size: expected 1 to " + std::to_string(kMaxImageSide) +
                                " pixels a side");
  }
  if (o.spp < 1 || o.spp > kMaxSpp) {
    throw std::invalid_argument("spp: expected 1 to " + std::to_string(kMaxSpp));
  }
  if (o.threads < 0 || o.threads > kMaxThreads) {
    throw std::invalid_argument("threads: expected 0 (all) to " + std::to_string(kMaxThreads));
  }
  o.share.check(tile_count(o.width, o.height));
}

}  // namespace

constexpr std::array<std::string_view, 3> kAccelNames = {"auto", "bvh", "brute"};

std::size_t tile_count(int width, int height) {
  const auto side = [](int n) { return (static_cast<std::size_t>(n) + kTileSize - 1) / kTileSize; };
  return side(width) * side(height);
}

TileRect tile_rect(std::size_t tile, int image_width, int image_height) {
  const std::size_t across = (static_cast<std::size_t>(image_width) + kTileSize - 1) / kTileSize;
  const int x0 = static_cast<int>(tile % across) * kTileSize;
  const int y0 = static_cast<int>(tile / across) * kTileSize;
  return {x0, y0, std::min(kTileSize, image_width - x0), std::min(kTileSize, image_height - y0)};
}

void TileShare::check(std::size_t tiles) const {
  if (count < 1 || index < 0 || index >= count)
    throw std::invalid_argument("tile share: expected 0 <= index < count");
  if (!listed) return;
  for (std::size_t k = 0; k < listed->size(); ++k) {
    if ((*listed)[k] >= tiles || (k > 0 && (*listed)[k] <= (*listed)[k - 1]))
      throw std::invalid_argument(
          "tile share: expected listed tiles strictly ascending and within the image");
  }
}

std::vector<std::string> accel_names() {
  return {kAccelNames.begin(), kAccelNames.end()};
}

std::optional<Accel> parse_accel(std::string_view name) {
  for (std::size_t i = 0; i < kAccelNames.size(); ++i) {
    if (kAccelNames[i] == name) return static_cast<Accel>(i);
  }
  return std::nullopt;
}

std::vector<std::string> mode_names() {
  return {kModeNames.begin(), kModeNames.end()};
}

std::string_view mode_name(Mode mode) {
  return kModeNames[static_cast<std::size_t>(mode)];
}

std::optional<Mode> parse_mode(std::string_view name) {
  for (std::size_t i = 0; i < kModeNames.size(); ++i) {
    if (kModeNames[i] == name) return static_cast<Mode>(i);
  }
  return std::nullopt;
}

Vec3 sky(const Ray& ray) {
  // Ray Tracing in One Weekend, chapter 4: white to sky blue by the direction's height.
  float a = 0.5f * (normalize(ray.dir).y + 1.0f);
  return (1.0f - a) * Vec3{1, 1, 1} + a * Vec3{0.5f, 0.7f, 1.0f};
}

std::uint8_t to_byte(float c) {
  // NaN compares false both ways and lands on 0.
  float clamped = c > 0.0f ? std::min(c, 1.0f) : 0.0f;
  return static_cast<std::uint8_t>(255.999f * clamped);
}

Image render(const Scene& scene, const RenderOptions& options, const Progress& progress,
             RenderStats* stats) {
  check_options(options);
  if (options.precision == Precision::float64)
    return render_in_double(scene, options, progress, stats);
  if (options.mode == Mode::path) return render_path(scene, options, progress, stats);
  auto build_start = std::chrono::steady_clock::now();
  SceneQueries queries(scene.spheres, options.accel, options.threads);
  auto build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - build_start).count();
  Image image = render(scene, queries, options, progress, stats);
  if (stats != nullptr) {
    stats->build_seconds = queries.uses_bvh() ? build_seconds : 0.0;
    stats->bvh = queries.uses_bvh();
  }
  return image;
}

Image render(const Scene& scene, const RayQueries& queries, const RenderOptions& options,
             const Progress& progress, RenderStats* stats) {
  check_options(options);
  if (options.precision != Precision::float32) {
    throw std::invalid_argument(
        "precision: expected float with the caller's queries (they answer float rays)");
  }
  if (options.mode == Mode::path) return render_path(scene, queries, options, progress, stats);
  check_share(queries, options);
  const Camera camera(scene.camera, options.width, options.height);
  const Shader<float> shader(scene, scene.spheres.view(), options.mode,
                             depth_scale(scene.camera.lookfrom, scene.camera.lookat));
  Image image =
      trace_frame(camera, queries, shader, queries.collective(), options, progress, stats);
  if (queries.collective()) queries.finish();
  return image;
}

}  // namespace sphray::render
