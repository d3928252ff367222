// What the renderer adds to the kernel: rays per second of a normals render against the
// kernel's own stream rate on the same camera rays, and the renderer's other work timed alone.
//
//   sphray_render_overhead [--scene rtiow-final] [--width 1920] [--height 1080] [--threads N]
//
// Each figure is the best of --repeat runs (the machine is shared; the best is the least
// disturbed). Single-threaded phases first, then the same comparison on N threads.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "frame/scene_queries.hpp"
#include "sphray/render/camera.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"
#include "sphray/sphray.hpp"

namespace {

using namespace sphray;
using namespace sphray::render;

template <class F>
double best_seconds(int repeat, F&& work) {
  double best = 1e300;
  for (int i = 0; i < repeat; ++i) {
    auto start = std::chrono::steady_clock::now();
    work();
    best = std::min(
        best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

void report(const char* what, std::size_t rays, double seconds) {
  std::printf("  %-48s %8.1f ms  %7.2f Mrays/s\n", what, seconds * 1e3,
              static_cast<double>(rays) / seconds / 1e6);
}

// Camera rays through the pixel centres, row by row, as the renderer makes them for spp 1.
std::vector<Ray> camera_rays(const Camera& camera) {
  std::vector<Ray> rays;
  rays.reserve(static_cast<std::size_t>(camera.width()) *
               static_cast<std::size_t>(camera.height()));
  for (int y = 0; y < camera.height(); ++y) {
    for (int x = 0; x < camera.width(); ++x) {
      rays.push_back(camera.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f));
    }
  }
  return rays;
}

// The kernel on the whole stream, cut into tile-sized pieces shared among the arena's threads.
void stream_in_tiles(const SceneQueries& queries, const std::vector<Ray>& rays,
                     std::vector<Hit>& hits) {
  constexpr std::size_t kTileRays = kTileSize * kTileSize;
  std::size_t pieces = (rays.size() + kTileRays - 1) / kTileRays;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pieces, 1), [&](const auto& range) {
    for (std::size_t p = range.begin(); p != range.end(); ++p) {
      std::size_t first = p * kTileRays, n = std::min(kTileRays, rays.size() - first);
      queries.intersect(std::span(rays.data() + first, n), std::span(hits.data() + first, n));
    }
  });
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Rays per second of the renderer against the kernel's stream on the same rays"};
  std::string scene_name = "rtiow-final";
  int width = 1920, height = 1080, threads = 0, repeat = 3;
  app.add_option("--scene", scene_name)->capture_default_str();
  app.add_option("--width", width)->check(CLI::Range(1, kMaxImageSide))->capture_default_str();
  app.add_option("--height", height)->check(CLI::Range(1, kMaxImageSide))->capture_default_str();
  app.add_option("--threads", threads, "0: all cores")->capture_default_str();
  app.add_option("--repeat", repeat)->check(CLI::Range(1, 100))->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  Scene scene = load_scene_or_preset(scene_name);
  Camera camera(scene.camera, width, height);
  std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::vector<Ray> rays = camera_rays(camera);
  std::vector<Hit> hits(n);
  std::vector<std::uint8_t> rgb(3 * n);
  int all = tbb::task_arena(tbb::task_arena::automatic).max_concurrency();
  int many = threads > 0 ? threads : all;
  tbb::task_arena arena(many);
  std::printf("%s, %zu spheres, %dx%d normals, spp 1, isa %s, best of %d\n", scene.name.c_str(),
              scene.spheres.size(), width, height, std::string(isa_name(active_isa())).c_str(),
              repeat);
  report("camera rays alone, 1 thread", n,
         best_seconds(repeat, [&] { rays = camera_rays(camera); }));

  for (Accel accel : {Accel::brute_force, Accel::bvh}) {
    SceneQueries queries(scene.spheres, accel);
    std::printf("%s:\n", accel == Accel::bvh ? "bvh" : "brute force");
    auto shade_all = [&] {
      for (std::size_t i = 0; i < n; ++i) {
        Vec3 c = hits[i].found() ? 0.5f * (queries.surface(rays[i], hits[i]).normal + Vec3{1, 1, 1})
                                 : sky(rays[i]);
        rgb[3 * i] = to_byte(c.x);
        rgb[3 * i + 1] = to_byte(c.y);
        rgb[3 * i + 2] = to_byte(c.z);
      }
    };
    RenderOptions options;
    options.width = width;
    options.height = height;
    options.accel = accel;
    auto render_seconds = [&](int t) {
      options.threads = t;
      double best = 1e300;
      for (int i = 0; i < repeat; ++i) {
        RenderStats stats;
        sphray::render::render(scene, options, {}, &stats);
        best = std::min(best, stats.seconds);
      }
      return best;
    };
    for (int t : {1, many}) {
      double kernel = best_seconds(repeat, [&] {
        tbb::task_arena(t).execute([&] { stream_in_tiles(queries, rays, hits); });
      });
      std::string label = std::to_string(t) + (t == 1 ? " thread" : " threads");
      report(("kernel stream alone (tile-sized calls), " + label).c_str(), n, kernel);
      if (t == 1)
        report("shading alone (surface, 0.5(n+1) or sky, bytes)", n,
               best_seconds(repeat, shade_all));
      double whole = render_seconds(t);
      report(("render, " + label).c_str(), n, whole);
      std::printf("  render rate / kernel rate: %.2f\n", kernel / whole);
      if (t == many) break;
    }
  }
  return 0;
}
