#include "sphray/render/renderer.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "scene_queries.hpp"
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

// SplitMix64's finaliser: a well-mixed 64-bit value from any counter.
std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
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

// Shades one ray's hit in the chosen mode. Everything but shaded mode's shadow ray is
// arithmetic on the hit and the surface the kernel reports.
class Shader {
 public:
  Shader(const Scene& scene, const SceneQueries& queries, Mode mode)
      : scene_(scene), queries_(queries), mode_(mode) {
    // Depth: grey = D / (D + distance), D the camera's distance to what it looks at, so the
    // point of interest is mid-grey whatever the scene's scale.
    depth_scale_ = length(scene.camera.lookfrom - scene.camera.lookat);
  }

  // Whether shading needs a shadow ray per hit (shaded mode): render_tile then traces them
  // all as one stream before shading.
  bool casts_shadows() const { return mode_ == Mode::shaded; }

  // Shaded mode: the cosine of the sun on the surface the ray hit, and if positive the shadow
  // ray that decides whether the sun reaches it (else 0 and no ray).
  float sun_cosine(const Ray& ray, const Hit& hit, Ray& shadow) const {
    if (!hit.found()) return 0.0f;
    Surface s = queries_.surface(ray, hit);
    Vec3 normal = s.front_face ? s.normal : -s.normal;
    float cosine = dot(normal, kLight);
    if (cosine <= 0.0f) return 0.0f;
    // Start the shadow ray a little off the surface, relative to the point's magnitude, so
    // rounding cannot put it back inside the sphere it leaves.
    Vec3 p = s.point;
    float scale = std::max({1.0f, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    shadow = Ray{p + (1e-4f * scale) * normal, kLight};
    return cosine;
  }

  // light: in shaded mode, the sun's cosine where its shadow ray was not blocked, else 0.
  Vec3 shade(const Ray& ray, const Hit& hit, float light) const {
    if (!hit.found()) return mode_ == Mode::depth || mode_ == Mode::id ? Vec3{0, 0, 0} : sky(ray);
    switch (mode_) {
      case Mode::normals:
        return 0.5f * (queries_.surface(ray, hit).normal + Vec3{1, 1, 1});
      case Mode::flat:
        return {1, 0, 0};
      case Mode::depth: {
        float grey = depth_scale_ / (depth_scale_ + hit.t * length(ray.dir));
        return {grey, grey, grey};
      }
      case Mode::id:
        return id_color(hit.id);
      case Mode::shaded:
        return (kAmbient + (1.0f - kAmbient) * light) * scene_.colors[hit.id];
      case Mode::path:
        break;  // render_path
    }
    return {0, 0, 0};
  }

  // The output byte of an averaged colour; shaded mode is gamma-2 encoded as in the book.
  float encode(float c) const { return mode_ == Mode::shaded ? std::sqrt(std::max(c, 0.0f)) : c; }

 private:
  const Scene& scene_;
  const SceneQueries& queries_;
  Mode mode_;
  float depth_scale_;
};

struct TileRect {
  int x0, y0, width, height;
};

TileRect tile_rect(std::size_t tile, int image_width, int image_height) {
  int tiles_across = (image_width + kTileSize - 1) / kTileSize;
  int x0 = static_cast<int>(tile % static_cast<std::size_t>(tiles_across)) * kTileSize;
  int y0 = static_cast<int>(tile / static_cast<std::size_t>(tiles_across)) * kTileSize;
  return {x0, y0, std::min(kTileSize, image_width - x0), std::min(kTileSize, image_height - y0)};
}

// Renders one tile into image: per sample, the tile's camera rays go to the kernel as one
// stream, in shaded mode then the shadow rays of their hits as another (both coherent: the
// kernel takes them in packets), then each hit is shaded and summed. Fixed-size buffers on the
// stack: no allocation.
std::uint64_t render_tile(const TileRect& r, const Camera& camera, const SceneQueries& queries,
                          const Shader& shader, const RenderOptions& options, Image& image) {
  std::array<Ray, kTilePixels> rays;
  std::array<Hit, kTilePixels> hits;
  std::array<Vec3, kTilePixels> sum{};
  std::array<float, kTilePixels> light{};
  std::array<Ray, kTilePixels> shadows;
  std::array<bool, kTilePixels> blocked;
  std::array<std::uint16_t, kTilePixels> shadow_pixel;
  std::size_t n = static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height);
  std::uint64_t shadow_rays = 0;
  for (int s = 0; s < options.spp; ++s) {
    for (std::size_t i = 0; i < n; ++i) {
      int x = r.x0 + static_cast<int>(i) % r.width;
      int y = r.y0 + static_cast<int>(i) / r.width;
      std::uint64_t pixel =
          static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(image.width) +
          static_cast<std::uint64_t>(x);
      auto [jx, jy] = jitter(pixel, options.spp, s, options.seed);
      rays[i] = camera.ray(static_cast<float>(x) + jx, static_cast<float>(y) + jy);
    }
    queries.intersect(std::span(rays.data(), n), std::span(hits.data(), n));
    if (shader.casts_shadows()) {
      std::size_t m = 0;
      for (std::size_t i = 0; i < n; ++i) {
        light[i] = shader.sun_cosine(rays[i], hits[i], shadows[m]);
        if (light[i] > 0.0f) shadow_pixel[m++] = static_cast<std::uint16_t>(i);
      }
      queries.occluded(std::span(shadows.data(), m), std::span(blocked.data(), m));
      for (std::size_t k = 0; k < m; ++k)
        if (blocked[k]) light[shadow_pixel[k]] = 0.0f;
      shadow_rays += m;
    }
    for (std::size_t i = 0; i < n; ++i)
      sum[i] += shader.shade(rays[i], hits[i], light[i]);
  }
  float inverse_spp = 1.0f / static_cast<float>(options.spp);
  for (std::size_t i = 0; i < n; ++i) {
    int x = r.x0 + static_cast<int>(i) % r.width;
    int y = r.y0 + static_cast<int>(i) / r.width;
    std::size_t pixel = static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                        static_cast<std::size_t>(x);
    std::uint8_t* out = &image.rgb[3 * pixel];
    Vec3 c = sum[i] * inverse_spp;
    out[0] = to_byte(shader.encode(c.x));
    out[1] = to_byte(shader.encode(c.y));
    out[2] = to_byte(shader.encode(c.z));
  }
  return shadow_rays;
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
}

}  // namespace

constexpr std::array<std::string_view, 3> kAccelNames = {"auto", "bvh", "brute"};

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
  if (options.mode == Mode::path) return render_path(scene, options, progress, stats);
  Camera camera(scene.camera, options.width, options.height);
  auto build_start = std::chrono::steady_clock::now();
  SceneQueries queries(scene.spheres, options.accel, options.threads);
  auto build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - build_start).count();
  Shader shader(scene, queries, options.mode);
  Image image{options.width, options.height,
              std::vector<std::uint8_t>(3 * static_cast<std::size_t>(options.width) *
                                        static_cast<std::size_t>(options.height))};
  std::size_t tiles_across = (static_cast<std::size_t>(options.width) + kTileSize - 1) / kTileSize;
  std::size_t tiles_down = (static_cast<std::size_t>(options.height) + kTileSize - 1) / kTileSize;
  std::size_t tiles = tiles_across * tiles_down;
  std::atomic<std::size_t> done{0};
  std::atomic<std::uint64_t> shadow_rays{0};
  std::atomic<std::uint64_t> camera_rays{0};

  auto start = std::chrono::steady_clock::now();
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tiles, 1), [&](const auto& range) {
      for (std::size_t t = range.begin(); t != range.end(); ++t) {
        TileRect rect = tile_rect(t, options.width, options.height);
        shadow_rays += render_tile(rect, camera, queries, shader, options, image);
        std::size_t finished = ++done;
        camera_rays += static_cast<std::uint64_t>(rect.width) *
                       static_cast<std::uint64_t>(rect.height) *
                       static_cast<std::uint64_t>(options.spp);
        if (progress) progress(finished, tiles, {camera_rays, 0, shadow_rays});
      }
    });
  });
  auto seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (stats != nullptr) {
    stats->seconds = seconds;
    stats->build_seconds = queries.uses_bvh() ? build_seconds : 0.0;
    stats->bvh = queries.uses_bvh();
    stats->camera_rays = static_cast<std::uint64_t>(options.width) *
                         static_cast<std::uint64_t>(options.height) *
                         static_cast<std::uint64_t>(options.spp);
    stats->shadow_rays = shadow_rays;
    stats->spp = options.spp;
  }
  return image;
}

}  // namespace sphray::render
