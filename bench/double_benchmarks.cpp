// Double precision against float in one run: each instruction set's brute force and tree, one
// query per ray, on the same scenes and rays (the float workload's, converted to double once
// outside the timed loop), and Embree's rtcIntersect1 (float) on the tree's. Each precision's
// hits are checked against its own scalar reference first.
//   double/<scene>/<kind>/<isa>/<float|double>          brute force
//   double-tree/<scene>/<kind>/<isa>/<float|double>     SphereBVH, SphereBVHd (isa auto: as
//                                                        built without one)
//   double-tree/<scene>/<kind>/embree/float             rtcIntersect1, one thread
//   double-points/<scene>/nearest/auto/<float|double>    nearest(tree, point) at the incoherent
//                                                        rays' origins
#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "implementations.hpp"

namespace sphray::bench {
namespace {

// A workload's spheres and brute-force rays in double.
struct DoubleWorkload {
  std::vector<double> cx, cy, cz, r;
  std::vector<Rayd> rays;

  // The brute-force rays, or all of them (the tree's).
  DoubleWorkload(const Workload& w, bool all_rays) {
    const SphereView v = w.view();
    cx.assign(v.cx, v.cx + v.count), cy.assign(v.cy, v.cy + v.count);
    cz.assign(v.cz, v.cz + v.count), r.assign(v.radius, v.radius + v.count);
    for (const Ray& ray : all_rays ? w.rays : w.brute_rays)
      rays.push_back({{ray.origin.x, ray.origin.y, ray.origin.z},
                      {ray.dir.x, ray.dir.y, ray.dir.z},
                      ray.tmin,
                      ray.tmax,
                      ray.mask});
  }
  SphereViewd view() const { return {cx.data(), cy.data(), cz.data(), r.data(), cx.size()}; }
};

// Whether the kernel returns its precision's scalar reference bits on the first rays.
template <class View, class Rays, class Query, class Reference>
bool agrees(const View& view, const Rays& rays, Query query, Reference reference) {
  for (std::size_t i = 0; i < rays.size() && i < kSampleRays; ++i) {
    const auto got = query(view, rays[i]);
    const auto want = reference(view, rays[i]);
    if (got.id != want.id || !(got.t == want.t || (got.t != got.t && want.t != want.t)))
      return false;
  }
  return true;
}

template <class View, class Rays, class Query>
void time_queries(benchmark::State& state, const View& view, const Rays& rays, Query query) {
  std::size_t found = 0;
  for (auto _ : state) {
    for (const auto& ray : rays) {
      const auto hit = query(view, ray);
      found += hit.found() ? 1 : 0;
      benchmark::DoNotOptimize(hit);
    }
  }
  const auto count = static_cast<std::int64_t>(rays.size());
  state.SetItemsProcessed(state.iterations() * count);
  state.counters["rays"] = static_cast<double>(count);
  state.counters["spheres"] = static_cast<double>(view.count);
  state.counters["hit_fraction"] =
      static_cast<double>(found) / static_cast<double>(state.iterations() * count);
}

void run(benchmark::State& state, std::string_view scene, RayKind kind, const EntryTable& k,
         bool in_double) {
  const Workload& w = workload(scene, kind);
  if (!in_double) {
    if (!agrees(w.view(), w.brute_rays, k.intersect,
                static_cast<Hit (*)(SphereView, const Ray&)>(&scalar::intersect)))
      return state.SkipWithError("float disagrees with the scalar reference");
    return time_queries(state, w.view(), w.brute_rays, k.intersect);
  }
  const DoubleWorkload d(w, false);
  if (!agrees(d.view(), d.rays, k.intersect_d,
              static_cast<Hitd (*)(SphereViewd, const Rayd&)>(&scalar::intersect)))
    return state.SkipWithError("double disagrees with the scalar reference");
  time_queries(state, d.view(), d.rays, k.intersect_d);
}

// The trees, built outside the timed loop for instruction set isa, or without one (the
// instruction set bvh_isa() picks: what a caller gets), one query per ray.
void run_tree(benchmark::State& state, std::string_view scene, RayKind kind, std::optional<Isa> isa,
              bool in_double) {
  const Workload& w = workload(scene, kind);
  if (!in_double) {
    const SphereBVH tree = isa ? SphereBVH(w.view(), *isa) : SphereBVH(w.view());
    const auto query = [&tree](SphereView, const Ray& ray) { return intersect(tree, ray); };
    if (!agrees(w.view(), w.rays, query,
                static_cast<Hit (*)(SphereView, const Ray&)>(&scalar::intersect)))
      return state.SkipWithError("the float tree disagrees with the scalar reference");
    return time_queries(state, w.view(), w.rays, query);
  }
  const DoubleWorkload d(w, true);
  const SphereBVHd tree = isa ? SphereBVHd(d.view(), *isa) : SphereBVHd(d.view());
  const auto query = [&tree](SphereViewd, const Rayd& ray) { return intersect(tree, ray); };
  if (!agrees(d.view(), d.rays, query,
              static_cast<Hitd (*)(SphereViewd, const Rayd&)>(&scalar::intersect)))
    return state.SkipWithError("the double tree disagrees with the scalar reference");
  time_queries(state, d.view(), d.rays, query);
}

// The nearest sphere to each ray's origin, through a tree built without an instruction set (as a
// caller gets it), in float or in double on the same points; each precision's answers checked
// against its scalar reference first. Rate: points per second.
void run_points(benchmark::State& state, std::string_view scene, bool in_double) {
  const Workload& w = workload(scene, RayKind::incoherent);
  const auto time = [&state](const auto& tree, const auto& view, const auto& points) {
    for (std::size_t i = 0; i < points.size() && i < kSampleRays; ++i) {
      const auto got = nearest(tree, points[i]), want = scalar::nearest(view, points[i]);
      if (got.id != want.id || got.distance != want.distance)
        return state.SkipWithError("the tree disagrees with the scalar reference");
    }
    std::size_t inside_count = 0;
    for (auto _ : state) {
      for (const auto& p : points) {
        const auto n = nearest(tree, p);
        inside_count += n.distance < 0 ? 1 : 0;
        benchmark::DoNotOptimize(n);
      }
    }
    const auto count = static_cast<std::int64_t>(points.size());
    state.SetItemsProcessed(state.iterations() * count);
    state.counters["points"] = static_cast<double>(count);
    state.counters["spheres"] = static_cast<double>(view.count);
    state.counters["inside_fraction"] =
        static_cast<double>(inside_count) / static_cast<double>(state.iterations() * count);
  };
  if (!in_double) {
    std::vector<Vec3> points;
    for (const Ray& r : w.rays)
      points.push_back(r.origin);
    return time(SphereBVH(w.view()), w.view(), points);
  }
  const DoubleWorkload d(w, true);
  std::vector<Vec3d> points;
  for (const Rayd& r : d.rays)
    points.push_back(r.origin);
  time(SphereBVHd(d.view()), d.view(), points);
}

#if SPHRAY_BENCH_EMBREE
// Embree's rtcIntersect1 on one thread over the same rays, as `embree-intersect1` runs it.
void run_embree(benchmark::State& state, std::string_view scene, RayKind kind) {
  const Workload& w = workload(scene, kind);
  const std::vector<Implementation> impls = embree_implementations();
  const auto it = std::find_if(impls.begin(), impls.end(), [](const Implementation& i) {
    return i.name == "embree-intersect1" && i.threads == 1;
  });
  if (it == impls.end()) return state.SkipWithError("no single-thread rtcIntersect1");
  const Trace trace = it->prepare(w);
  std::vector<Hit> hits(w.rays.size());
  std::size_t found = 0;
  for (auto _ : state) {
    trace(w.rays, hits);
    found += static_cast<std::size_t>(
        std::count_if(hits.begin(), hits.end(), [](const Hit& h) { return h.found(); }));
    benchmark::DoNotOptimize(hits.data());
  }
  const auto count = static_cast<std::int64_t>(w.rays.size());
  state.SetItemsProcessed(state.iterations() * count);
  state.counters["rays"] = static_cast<double>(count);
  state.counters["spheres"] = static_cast<double>(w.spheres.size());
  state.counters["hit_fraction"] =
      static_cast<double>(found) / static_cast<double>(state.iterations() * count);
}
#endif

}  // namespace

void register_double_benchmarks() {
  for (const std::string_view scene :
       {"three", "random:8", "rtiow-final", "random:64", "random:512"}) {
    for (const RayKind kind : {RayKind::coherent, RayKind::incoherent}) {
      for (const Isa isa : supported_isas()) {
        const EntryTable& k = *find_entries(isa);
        for (const bool in_double : {false, true}) {
          const std::string name = "double/" + std::string(scene) + "/" +
                                   std::string(ray_kind_name(kind)) + "/" +
                                   std::string(isa_name(isa)) + (in_double ? "/double" : "/float");
          benchmark::RegisterBenchmark(name.c_str(),
                                       [scene, kind, &k, in_double](benchmark::State& s) {
                                         run(s, scene, kind, k, in_double);
                                       })
              ->UseRealTime()
              ->Unit(benchmark::kMillisecond);
        }
      }
    }
  }
  for (const std::string_view scene : {"rtiow-final", "random:4096", "random:65536"}) {
    for (const RayKind kind : {RayKind::coherent, RayKind::incoherent}) {
      const std::string prefix =
          "double-tree/" + std::string(scene) + "/" + std::string(ray_kind_name(kind)) + "/";
      std::vector<std::optional<Isa>> isas{std::nullopt};
      for (const Isa isa : supported_isas())
        isas.emplace_back(isa);
      for (const std::optional<Isa> isa : isas) {
        for (const bool in_double : {false, true}) {
          const std::string name = prefix + std::string(isa ? isa_name(*isa) : "auto") +
                                   (in_double ? "/double" : "/float");
          benchmark::RegisterBenchmark(name.c_str(),
                                       [scene, kind, isa, in_double](benchmark::State& s) {
                                         run_tree(s, scene, kind, isa, in_double);
                                       })
              ->UseRealTime()
              ->Unit(benchmark::kMillisecond);
        }
      }
#if SPHRAY_BENCH_EMBREE
      benchmark::RegisterBenchmark(
          (prefix + "embree/float").c_str(),
          [scene, kind](benchmark::State& s) { run_embree(s, scene, kind); })
          ->UseRealTime()
          ->Unit(benchmark::kMillisecond);
#endif
    }
  }
  for (const std::string_view scene : {"rtiow-final", "random:4096", "random:65536"}) {
    for (const bool in_double : {false, true}) {
      const std::string name = "double-points/" + std::string(scene) + "/nearest/auto" +
                               (in_double ? "/double" : "/float");
      benchmark::RegisterBenchmark(
          name.c_str(),
          [scene, in_double](benchmark::State& s) { run_points(s, scene, in_double); })
          ->UseRealTime()
          ->Unit(benchmark::kMillisecond);
    }
  }
}

}  // namespace sphray::bench
