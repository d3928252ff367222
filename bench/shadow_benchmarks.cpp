// Shadow rays towards one light, as the renderer's shaded mode traces them: from where the
// coherent camera rays of a 512 x 512 frame hit, a little off the surface, towards the sun
// (one direction for all). Occlusion queries only: the tree per ray and as a stream (packets
// where they win), against Embree's rtcOccluded1/8/16. Each is checked against the scalar
// reference on a sample first. Names: shadow/<scene>/<implementation>/threads:1.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "implementations.hpp"
#include "workload.hpp"

namespace sphray::bench {
namespace {

constexpr std::size_t kSample = 1024;

// The renderer's sun (render/src/frame/renderer.cpp).
Vec3 sun() {
  return normalize(Vec3{0.6f, 1.0f, 0.45f});
}

// The shadow rays of the scene's camera rays, in pixel order, for the hits that face the sun.
std::vector<Ray> make_shadow_rays(const Workload& w) {
  const SphereBVH tree(w.view());
  std::vector<Hit> hits(w.rays.size());
  intersect(tree, w.rays, hits);
  std::vector<Ray> shadows;
  for (std::size_t i = 0; i < hits.size(); ++i) {
    if (!hits[i].found()) continue;
    const Surface s = surface(w.view(), w.rays[i], hits[i]);
    const Vec3 normal = s.front_face ? s.normal : -s.normal;
    if (dot(normal, sun()) <= 0.0f) continue;
    const Vec3 p = s.point;
    const float scale = std::max({1.0f, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    shadows.push_back({p + (1e-4f * scale) * normal, sun()});
  }
  return shadows;
}

struct ShadowScene {
  std::string name;
  std::vector<Ray> rays;
  std::vector<char> expected;  // the scalar reference on the first kSample rays
};

const ShadowScene& shadow_scene(std::string_view name) {
  static std::unique_ptr<ShadowScene> kept;
  if (kept && kept->name == name) return *kept;
  const Workload& w = workload(name, RayKind::coherent);
  auto s = std::make_unique<ShadowScene>();
  s->name = name;
  s->rays = make_shadow_rays(w);
  for (std::size_t i = 0; i < std::min(kSample, s->rays.size()); ++i)
    s->expected.push_back(scalar::occluded(w.view(), s->rays[i]));
  kept = std::move(s);
  return *kept;
}

void run(benchmark::State& state, std::string_view scene_name, const Occluder& occluder) {
  const ShadowScene& s = shadow_scene(scene_name);
  const Occlusion trace = occluder.prepare(workload(scene_name, RayKind::coherent));
  std::unique_ptr<bool[]> blocked(new bool[s.rays.size()]);
  trace(std::span(s.rays.data(), s.expected.size()), blocked.get());
  for (std::size_t i = 0; i < s.expected.size(); ++i) {
    if (blocked[i] != (s.expected[i] != 0)) {
      state.SkipWithError("disagrees with the scalar reference");
      return;
    }
  }
  for (auto _ : state) {
    trace(s.rays, blocked.get());
    benchmark::DoNotOptimize(blocked.get());
  }
  const auto blocked_count = std::count(blocked.get(), blocked.get() + s.rays.size(), true);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(s.rays.size()));
  state.counters["rays"] = static_cast<double>(s.rays.size());
  state.counters["blocked"] =
      static_cast<double>(blocked_count) / static_cast<double>(s.rays.size());
}

// The tree built once per scene.
std::shared_ptr<const SphereBVH> tree_for(const Workload& w) {
  static std::string built_for;
  static std::shared_ptr<const SphereBVH> tree;
  if (!tree || built_for != w.scene) {
    tree.reset();
    tree = std::make_shared<const SphereBVH>(w.view());
    built_for = w.scene;
  }
  return tree;
}

std::vector<Occluder> tree_occluders() {
  Occluder per_ray{"bvh", [](const Workload& w) -> Occlusion {
                     return [t = tree_for(w)](std::span<const Ray> rays, bool* blocked) {
                       for (std::size_t i = 0; i < rays.size(); ++i)
                         blocked[i] = occluded(*t, rays[i]);
                     };
                   }};
  Occluder stream{"bvh-stream", [](const Workload& w) -> Occlusion {
                    return [t = tree_for(w)](std::span<const Ray> rays, bool* blocked) {
                      occluded(*t, rays, std::span<bool>(blocked, rays.size()));
                    };
                  }};
  return {per_ray, stream};
}

}  // namespace

void register_shadow_benchmarks() {
  std::vector<Occluder> occluders = tree_occluders();
#if SPHRAY_BENCH_EMBREE
  for (Occluder& o : embree_occluders())
    occluders.push_back(std::move(o));
#endif
  for (std::string_view scene_name :
       {"rtiow-final", "random:4096", "random:65536", "random:1048576"}) {
    for (const Occluder& o : occluders) {
      const std::string name = "shadow/" + std::string(scene_name) + "/" + o.name + "/threads:1";
      benchmark::RegisterBenchmark(name.c_str(),
                                   [scene_name, o](benchmark::State& s) { run(s, scene_name, o); })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
}

}  // namespace sphray::bench
