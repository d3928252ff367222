// The benchmark bodies: verify, then time passes over the rays; and build timings.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <tuple>

#include <benchmark/benchmark.h>

#include "bench/bench_agreement.hpp"
#include "implementations.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

namespace sphray::bench {
namespace {

using render::bench::Agreement;
using render::bench::compare_hits;

// Time stamp counter ticks: constant rate (the nominal clock) on every CPU this runs on,
// whatever the core clock does. The "clock" benchmark relates the two.
std::uint64_t ticks() {
#if defined(__x86_64__) || defined(__i386__)
  return __rdtsc();
#else
  return 0;
#endif
}

std::size_t found_count(std::span<const Hit> hits) {
  return static_cast<std::size_t>(
      std::count_if(hits.begin(), hits.end(), [](const Hit& h) { return h.found(); }));
}

// Each implementation is checked once per workload; Google Benchmark enters a benchmark
// several times (to size its iteration count), and a check on a million spheres is not free.
const Agreement& check(const std::string& key, const Workload& w, const Trace& trace) {
  static std::map<std::string, Agreement> checked;
  auto it = checked.find(key);
  if (it == checked.end()) {
    std::vector<Hit> got(w.sample.size());
    trace(w.sample, got);
    it = checked.emplace(key, compare_hits(w.sample, w.expected, got)).first;
  }
  return it->second;
}

// The fraction of (ray, batch of `width` spheres) pairs in which some sphere's discriminant is
// non-negative: the batches the kernel cannot skip. With it, the bound per batch of the
// kernel's two paths (see bench/count_loop.py) blends into the bound for this workload.
double live_batch_fraction(const Workload& w, std::size_t width) {
  static std::map<std::tuple<std::string, RayKind, std::size_t>, double> known;
  const auto key = std::make_tuple(w.scene, w.kind, width);
  if (auto it = known.find(key); it != known.end()) return it->second;
  const std::size_t n = w.spheres.size();
  const std::size_t batches = (n + width - 1) / width;
  std::size_t live = 0;
  for (const Ray& ray : w.brute_rays) {
    const float a = dot(ray.dir, ray.dir);
    for (std::size_t b = 0; b < batches; ++b) {
      bool any = false;
      for (std::size_t i = b * width; i < std::min(n, (b + 1) * width) && !any; ++i) {
        const auto id = static_cast<std::uint32_t>(i);
        const Vec3 g = w.spheres.center(id) - ray.origin;
        const Vec3 v = (dot(g, ray.dir) / a) * ray.dir - g;
        const float r = w.spheres.radius(id);
        any = r > 0.0f && r * r - dot(v, v) >= 0.0f;
      }
      live += any ? 1 : 0;
    }
  }
  return known[key] =
             static_cast<double>(live) / static_cast<double>(w.brute_rays.size() * batches);
}

// TSC ticks per sphere test of a single-thread brute force tracer, robust against a shared
// machine: the rays are cut into chunks of about 2^14 tests, each chunk is timed in three
// passes, and the fastest pass of each chunk counts. A chunk whose pass was interrupted by
// another process is simply slower in that pass; the chunks' content stays the whole set.
double ticks_per_test(const std::string& key, const Workload& w, const Trace& trace) {
  static std::map<std::string, double> known;
  if (auto it = known.find(key); it != known.end()) return it->second;
  const std::vector<Ray>& rays = w.brute_rays;
  const std::size_t chunk = std::max<std::size_t>(1, (std::size_t{1} << 14) / w.spheres.size());
  std::vector<Hit> hits(rays.size());
  std::vector<std::uint64_t> fastest((rays.size() + chunk - 1) / chunk, UINT64_MAX);
  for (int pass = 0; pass < 3; ++pass) {
    for (std::size_t c = 0; c < fastest.size(); ++c) {
      const std::size_t begin = c * chunk, n = std::min(chunk, rays.size() - begin);
      const std::uint64_t start = ticks();
      trace(std::span(rays).subspan(begin, n), std::span(hits).subspan(begin, n));
      fastest[c] = std::min(fastest[c], ticks() - start);
    }
  }
  double total = 0;
  for (std::uint64_t t : fastest)
    total += static_cast<double>(t);
  return known[key] =
             total / (static_cast<double>(rays.size()) * static_cast<double>(w.spheres.size()));
}

void trace_rays(benchmark::State& state, const std::string& name, std::string_view scene,
                RayKind kind, const Implementation& impl) {
  const Workload& w = workload(scene, kind);
  const Trace trace = impl.prepare(w);
  const Agreement& agreement = check(name, w, trace);
  if (!agreement.ok()) {
    state.SkipWithError(
        ("disagrees with the scalar reference: " + agreement.first_mismatch).c_str());
    return;
  }
  const std::vector<Ray>& rays = impl.brute_force ? w.brute_rays : w.rays;
  std::vector<Hit> hits(rays.size());
  for (auto _ : state) {
    trace(rays, hits);
    benchmark::DoNotOptimize(hits.data());
    benchmark::ClobberMemory();
  }
  const auto passes = static_cast<double>(state.iterations());
  const auto ray_count = static_cast<double>(rays.size());
  const auto spheres = static_cast<double>(w.spheres.size());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rays.size()));
  state.counters["spheres"] = spheres;
  state.counters["rays"] = ray_count;
  state.counters["threads"] = impl.threads;
  state.counters["hit_fraction"] = static_cast<double>(found_count(hits)) / ray_count;
  state.counters["id_ties"] = static_cast<double>(agreement.id_ties);
  if (!impl.brute_force) return;
  state.counters["sphere_tests_per_second"] =
      benchmark::Counter(passes * ray_count * spheres, benchmark::Counter::kIsRate);
  if (impl.threads == 1 && impl.width > 0) {
    state.counters["width"] = static_cast<double>(impl.width);
    state.counters["tsc_per_sphere"] = ticks_per_test(name, w, trace);
    state.counters["live_batch_fraction"] = live_batch_fraction(w, impl.width);
  }
}

void build(benchmark::State& state, std::string_view scene, const Builder& builder) {
  time_build(state, workload(scene, RayKind::coherent).spheres, builder);
}

std::string threads_suffix(int threads) {
  return "/threads:" + std::to_string(threads);
}

}  // namespace

void time_build(benchmark::State& state, const SphereSoA& spheres, const Builder& builder) {
  const std::function<Built()> step = builder.prepare(spheres);
  std::size_t bytes = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    Built built = step();
    const auto stop = std::chrono::steady_clock::now();
    state.SetIterationTime(std::chrono::duration<double>(stop - start).count());
    bytes = built.bytes;
    // built is released here, outside the measured interval
  }
  const auto n = static_cast<double>(spheres.size());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(spheres.size()));
  state.counters["spheres"] = n;
  state.counters["threads"] = builder.threads;
  state.counters["bytes_per_sphere"] = static_cast<double>(bytes) / n;
}

void register_benchmarks(const std::vector<Implementation>& implementations,
                         const std::vector<Builder>& builders) {
  for (std::string_view scene : scene_names()) {
    for (const Builder& b : builders) {
      const std::string name =
          "build/" + std::string(scene) + "/" + b.name + threads_suffix(b.threads);
      benchmark::RegisterBenchmark(name.c_str(),
                                   [scene, &b](benchmark::State& s) { build(s, scene, b); })
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond);
    }
    for (RayKind kind : ray_kinds(scene)) {
      for (const Implementation& impl : implementations) {
        const std::string name = "rays/" + std::string(scene) + "/" +
                                 std::string(ray_kind_name(kind)) + "/" + impl.name +
                                 threads_suffix(impl.threads);
        benchmark::RegisterBenchmark(name.c_str(),
                                     [name, scene, kind, &impl](benchmark::State& s) {
                                       trace_rays(s, name, scene, kind, impl);
                                     })
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond);
      }
    }
  }
}

}  // namespace sphray::bench
