// The queries beyond the closest hit (docs/queries.md), timed against the closest hit on the
// same rays: every crossing, their count, and the point queries, through the tree and by brute
// force where the scene is small. Each is checked against the scalar reference on a sample
// before it is timed. Names: queries/<scene>/<query>/<tree|brute>/threads:1.
//
// The every-crossing queries also run beside Embree's way to the same answer (an intersection
// filter that records each hit and rejects it), on camera and incoherent rays, each checked
// against the scalar reference's crossings on a sample (render/src/bench/bench_agreement.hpp).
// Names: every_hit/<scene>/<coherent|incoherent>/<row>/threads:1.
#include <algorithm>
#include <array>
#include <atomic>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_agreement.hpp"
#include "implementations.hpp"
#include "threads.hpp"
#include "workload.hpp"

namespace sphray::bench {
namespace {

using render::bench::Agreement;
using render::bench::compare_crossings;
using render::bench::Crossings;

constexpr std::size_t kPoints = 1 << 16;
constexpr std::size_t kSample = 256;
constexpr std::size_t kAllHitsRoom = 16;

struct Queries {
  const SphereBVH* tree = nullptr;  // null: brute force over the view
  SphereView view;
  float overlap_radius = 0.0f;
  const SphereBVH* masked_tree = nullptr;  // the same spheres, masks 1 and 2 alternating
  SphereView masked_view;
};

std::vector<Vec3> random_points(const Box& box, std::size_t count) {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Vec3> points(count);
  for (Vec3& p : points)
    p = {box.lo.x + (box.hi.x - box.lo.x) * u(rng), box.lo.y + (box.hi.y - box.lo.y) * u(rng),
         box.lo.z + (box.hi.z - box.lo.z) * u(rng)};
  return points;
}

// One query over a ray or a point, returning something to keep (and to check against the
// scalar reference: equal answers give equal values).

std::size_t closest(const Queries& q, const Ray& r) {
  const Hit h = q.tree ? intersect(*q.tree, r) : intersect(q.view, r);
  return h.id;
}
// Rays of mask 1 among spheres of masks 1 and 2 in turn: half the spheres hidden.
std::size_t closest_masked(const Queries& q, const Ray& r) {
  Ray masked = r;
  masked.mask = 1u;
  const Hit h = q.tree ? intersect(*q.masked_tree, masked) : intersect(q.masked_view, masked);
  return h.id;
}
std::size_t any_hit(const Queries& q, const Ray& r) {
  return q.tree ? occluded(*q.tree, r) : occluded(q.view, r);
}
std::size_t count(const Queries& q, const Ray& r) {
  return q.tree ? count_hits(*q.tree, r) : count_hits(q.view, r);
}
std::size_t all_hits(const Queries& q, const Ray& r) {
  std::array<Hit, kAllHitsRoom> out;
  const std::size_t n = q.tree ? intersect_all(*q.tree, r, out) : intersect_all(q.view, r, out);
  return n == 0 ? 0 : n * 31 + out[0].id;
}
// The K nearest crossings alone (the walk pruned at the K-th found so far).
template <std::size_t K>
std::size_t nearest_hits(const Queries& q, const Ray& r) {
  std::array<Hit, K> out;
  const std::size_t n =
      q.tree ? intersect_nearest(*q.tree, r, out) : intersect_nearest(q.view, r, out);
  return n == 0 ? 0 : n * 31 + out[0].id;
}
std::size_t nearest_id(const Queries& q, Vec3 p) {
  return (q.tree ? nearest(*q.tree, p) : nearest(q.view, p)).id;
}
std::size_t occupied(const Queries& q, Vec3 p) {
  return q.tree ? inside(*q.tree, p) : inside(q.view, p);
}
std::size_t overlaps(const Queries& q, Vec3 p) {
  std::array<std::uint32_t, 16> ids;
  return q.tree ? overlapping(*q.tree, p, q.overlap_radius, ids)
                : overlapping(q.view, p, q.overlap_radius, ids);
}

// A scene's spheres, rays, points and tree, kept while its benchmarks run (they run in order of
// registration, one scene after the other).
struct Scene {
  std::string name;
  SphereSoA spheres;
  std::vector<Ray> rays, brute_rays;
  std::vector<Vec3> points;
  SphereBVH tree;
  float median_radius = 0.0f;
  std::vector<std::uint32_t> masks;
  SphereBVH masked_tree;

  SphereView masked_view() const {
    SphereView v = spheres.view();
    v.mask = masks.data();
    return v;
  }
};

const Scene& scene(std::string_view name) {
  static std::unique_ptr<Scene> kept;
  if (kept && kept->name == name) return *kept;
  kept.reset();
  const Workload& w = workload(name, RayKind::incoherent);
  auto s = std::make_unique<Scene>();
  s->name = name;
  s->spheres = w.spheres;
  s->rays = w.rays;
  s->brute_rays = w.brute_rays;
  s->points = random_points(sphere_box(w.spheres), kPoints);
  s->tree = SphereBVH(s->spheres.view());
  s->masks.resize(s->spheres.view().padded_count);
  for (std::size_t i = 0; i < s->masks.size(); ++i)
    s->masks[i] = i % 2 == 0 ? 1u : 2u;
  s->masked_tree = SphereBVH(s->masked_view());
  std::vector<float> radii(s->spheres.view().radius, s->spheres.view().radius + s->spheres.size());
  std::nth_element(radii.begin(), radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2),
                   radii.end());
  s->median_radius = radii[radii.size() / 2];
  kept = std::move(s);
  return *kept;
}

// The timed loop of every row: the query over every item, its answers summed into a sink.
template <class Item, class Query>
void time_items(benchmark::State& state, std::span<const Item> items, std::size_t spheres,
                Query query) {
  std::size_t sink = 0;
  for (auto _ : state) {
    for (const Item& item : items)
      sink += query(item);
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(items.size()));
  state.counters["spheres"] = static_cast<double>(spheres);
  state.counters["queries"] = static_cast<double>(items.size());
}

template <class Item, class Query>
void run(benchmark::State& state, std::string_view scene_name, bool tree, Query query,
         std::size_t (*reference)(const Queries&, const Item&)) {
  const Scene& s = scene(scene_name);
  const Queries q{tree ? &s.tree : nullptr, s.spheres.view(), s.median_radius, &s.masked_tree,
                  s.masked_view()};
  const Queries ref{nullptr, s.spheres.view(), s.median_radius, nullptr, s.masked_view()};
  std::vector<Item> items;
  if constexpr (std::is_same_v<Item, Ray>) {
    items = tree ? s.rays : s.brute_rays;
  } else {
    items = s.points;
    if (!tree) items.resize(std::min(items.size(), s.brute_rays.size()));
  }
  // Checked on a sample against the scalar reference's answers.
  for (std::size_t i = 0; i < std::min(kSample, items.size()); ++i) {
    if (query(q, items[i]) != reference(ref, items[i])) {
      state.SkipWithError("disagrees with the scalar reference");
      return;
    }
  }
  time_items(state, std::span<const Item>(items), s.spheres.size(),
             [&](const Item& item) { return query(q, item); });
}

// The scalar reference's answers, in the form each query above returns.
std::size_t ref_closest(const Queries& q, const Ray& r) {
  return scalar::intersect(q.view, r).id;
}
std::size_t ref_closest_masked(const Queries& q, const Ray& r) {
  Ray masked = r;
  masked.mask = 1u;
  return scalar::intersect(q.masked_view, masked).id;
}
std::size_t ref_any(const Queries& q, const Ray& r) {
  return scalar::occluded(q.view, r);
}
std::size_t ref_count(const Queries& q, const Ray& r) {
  return scalar::intersect_all(q.view, r, {}, {});
}
std::size_t ref_all(const Queries& q, const Ray& r) {
  std::array<Hit, kAllHitsRoom> out;
  const std::size_t n = scalar::intersect_all(q.view, r, out, {});
  return n == 0 ? 0 : n * 31 + out[0].id;
}
template <std::size_t K>
std::size_t ref_nearest_hits(const Queries& q, const Ray& r) {
  std::array<Hit, K> out;
  const std::size_t n = std::min(scalar::intersect_all(q.view, r, out, {}), K);
  return n == 0 ? 0 : n * 31 + out[0].id;
}
std::size_t ref_nearest(const Queries& q, const Vec3& p) {
  return scalar::nearest(q.view, p).id;
}
std::size_t ref_inside(const Queries& q, const Vec3& p) {
  return scalar::overlapping(q.view, p, 0.0f, {}) > 0;
}
std::size_t ref_overlaps(const Queries& q, const Vec3& p) {
  std::array<std::uint32_t, 16> ids;
  return scalar::overlapping(q.view, p, q.overlap_radius, ids);
}

// A simulation step's broad phase: every sphere of the scene asks the tree which spheres
// overlap it. Rates: spheres asked per second, and overlapping pairs found per second (each
// unordered pair once; a sphere does not pair with itself). Checked first on a sample of
// spheres against the scalar reference's counts.
void broad_phase(benchmark::State& state, std::string_view scene_name, int threads) {
  const Scene& s = scene(scene_name);
  const SphereView view = s.spheres.view();
  constexpr std::size_t kRoom = 64;  // ids kept per query; the count is exact beyond it
  auto overlaps_of = [&](std::uint32_t i, std::span<std::uint32_t> ids) {
    return overlapping(s.tree, {view.cx[i], view.cy[i], view.cz[i]}, view.radius[i], ids);
  };
  const std::size_t step = std::max<std::size_t>(1, s.spheres.size() / 16);
  for (std::size_t k = 0; k < s.spheres.size(); k += step) {
    const auto i = static_cast<std::uint32_t>(k);
    std::array<std::uint32_t, kRoom> ids;
    const Vec3 c{view.cx[i], view.cy[i], view.cz[i]};
    if (overlaps_of(i, ids) != scalar::overlapping(view, c, view.radius[i], {})) {
      state.SkipWithError("disagrees with the scalar reference");
      return;
    }
  }
  std::atomic<std::size_t> pairs{0};
  for (auto _ : state) {
    pairs = 0;
    parallel_chunks(threads, s.spheres.size(), [&](std::size_t begin, std::size_t end) {
      std::array<std::uint32_t, kRoom> ids;
      std::size_t found = 0;
      for (std::size_t i = begin; i < end; ++i)
        found += overlaps_of(static_cast<std::uint32_t>(i), ids) - 1;  // less itself
      pairs += found;
    });
  }
  const auto n = static_cast<std::int64_t>(s.spheres.size());
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["spheres"] = static_cast<double>(n);
  state.counters["pairs"] = static_cast<double>(pairs.load() / 2);
  state.counters["pairs_per_second"] = benchmark::Counter(
      static_cast<double>(pairs.load() / 2) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
}

// --- Every crossing against Embree's filter ----------------------------------------------

// A scene and ray kind's rays, tree and Embree scenes, and the scalar reference's crossings on
// a sample, kept while its rows run.
struct CrossingScene {
  std::string name;
  RayKind kind;
  std::size_t spheres = 0;
  std::vector<Ray> rays, sample;
  std::vector<Crossings> expected;  // kAllHitsRoom kept
  SphereBVH tree;
#if SPHRAY_BENCH_EMBREE
  std::unique_ptr<EmbreeCrossings> embree_nearest, embree_count;
#endif
};

const CrossingScene& crossing_scene(std::string_view name, RayKind kind) {
  static std::unique_ptr<CrossingScene> kept;
  if (kept && kept->name == name && kept->kind == kind) return *kept;
  kept.reset();
  const Workload& w = workload(name, kind);
  auto s = std::make_unique<CrossingScene>();
  s->name = name;
  s->kind = kind;
  s->spheres = w.spheres.size();
  s->rays = w.rays;
  s->sample = w.sample;
  for (const Ray& r : s->sample) {
    Crossings c;
    c.nearest.resize(kAllHitsRoom);
    c.total = scalar::intersect_all(w.view(), r, c.nearest, {});
    c.nearest.resize(std::min(c.total, kAllHitsRoom));
    s->expected.push_back(std::move(c));
  }
  s->tree = SphereBVH(w.view());
#if SPHRAY_BENCH_EMBREE
  s->embree_nearest = std::make_unique<EmbreeCrossings>(w.spheres, false);
  s->embree_count = std::make_unique<EmbreeCrossings>(w.spheres, true);
#endif
  kept = std::move(s);
  return *kept;
}

// One row: the total, and the nearest crossings in out unless it only counts (out is
// kAllHitsRoom long).
struct CrossingRow {
  const char* name;
  bool counts_only;
  std::size_t (*query)(const CrossingScene&, const Ray&, std::span<Hit> out);
};

std::size_t tree_count(const CrossingScene& s, const Ray& r, std::span<Hit>) {
  return count_hits(s.tree, r);
}
std::size_t tree_all(const CrossingScene& s, const Ray& r, std::span<Hit> out) {
  return intersect_all(s.tree, r, out);
}
// intersect_nearest returns how many it wrote, not the total: the row's total is that count.
std::size_t tree_nearest(const CrossingScene& s, const Ray& r, std::span<Hit> out) {
  return intersect_nearest(s.tree, r, out);
}
#if SPHRAY_BENCH_EMBREE
std::size_t embree_count(const CrossingScene& s, const Ray& r, std::span<Hit>) {
  return s.embree_count->intersect_all(r, {});
}
std::size_t embree_all(const CrossingScene& s, const Ray& r, std::span<Hit> out) {
  return s.embree_nearest->intersect_all(r, out);
}
#endif

void run_crossings(benchmark::State& state, std::string_view scene_name, RayKind kind,
                   const CrossingRow& row) {
  const CrossingScene& s = crossing_scene(scene_name, kind);
  const bool writes_total = row.query != tree_nearest;
  std::vector<Crossings> got(s.sample.size()), expected = s.expected;
  for (std::size_t i = 0; i < s.sample.size(); ++i) {
    std::array<Hit, kAllHitsRoom> out;
    got[i].total = row.query(s, s.sample[i], out);
    if (!row.counts_only)
      got[i].nearest.assign(out.begin(), out.begin() + std::min(got[i].total, kAllHitsRoom));
    if (row.counts_only) expected[i].nearest.clear();
    if (!writes_total) expected[i].total = expected[i].nearest.size();
  }
  const Agreement a = compare_crossings(expected, got);
  if (!a.ok()) {
    state.SkipWithError(("disagrees with the scalar reference: " + a.first_mismatch).c_str());
    return;
  }
  state.counters["id_ties"] = static_cast<double>(a.id_ties);
  state.counters["undecided"] = static_cast<double>(a.undecided);
  time_items(state, std::span<const Ray>(s.rays), s.spheres, [&](const Ray& r) {
    std::array<Hit, kAllHitsRoom> out;
    const std::size_t n = row.query(s, r, out);
    return row.counts_only || n == 0 ? n : n * 31 + out[0].id;
  });
}

void register_crossing_benchmarks() {
  static const CrossingRow rows[] = {
    {"count_hits", true, tree_count},
#if SPHRAY_BENCH_EMBREE
    {"embree_filter_count", true, embree_count},
#endif
    {"intersect_all16", false, tree_all},
#if SPHRAY_BENCH_EMBREE
    {"embree_filter_all16", false, embree_all},
#endif
    {"intersect_nearest16", false, tree_nearest},
  };
  for (std::string_view scene_name :
       {std::string_view("rtiow-final"), std::string_view("random:4096"),
        std::string_view("random:65536")}) {
    for (const RayKind kind : {RayKind::coherent, RayKind::incoherent}) {
      for (const CrossingRow& row : rows) {
        const std::string name = "every_hit/" + std::string(scene_name) + "/" +
                                 std::string(ray_kind_name(kind)) + "/" + row.name + "/threads:1";
        benchmark::RegisterBenchmark(
            name.c_str(), [=](benchmark::State& s) { run_crossings(s, scene_name, kind, row); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }
}

}  // namespace

void register_query_benchmarks() {
  struct RayRow {
    const char* name;
    std::size_t (*query)(const Queries&, const Ray&);
    std::size_t (*reference)(const Queries&, const Ray&);
  };
  struct PointRow {
    const char* name;
    std::size_t (*query)(const Queries&, Vec3);
    std::size_t (*reference)(const Queries&, const Vec3&);
  };
  static const RayRow rays[] = {{"closest", closest, ref_closest},
                                {"closest_masked", closest_masked, ref_closest_masked},
                                {"occluded", any_hit, ref_any},
                                {"count_hits", count, ref_count},
                                {"intersect_all16", all_hits, ref_all},
                                {"intersect_nearest1", nearest_hits<1>, ref_nearest_hits<1>},
                                {"intersect_nearest16", nearest_hits<16>, ref_nearest_hits<16>}};
  static const PointRow points[] = {{"nearest", nearest_id, ref_nearest},
                                    {"inside", occupied, ref_inside},
                                    {"overlapping", overlaps, ref_overlaps}};
  for (std::string_view scene_name :
       {std::string_view("random:4096"), std::string_view("random:65536")}) {
    for (const bool tree : {true, false}) {
      if (!tree && scene_name != "random:4096") continue;  // brute force: the small scene only
      const std::string how = tree ? "tree" : "brute";
      for (const RayRow& r : rays) {
        const std::string name =
            "queries/" + std::string(scene_name) + "/" + r.name + "/" + how + "/threads:1";
        benchmark::RegisterBenchmark(
            name.c_str(),
            [=](benchmark::State& s) { run<Ray>(s, scene_name, tree, r.query, r.reference); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
      for (const PointRow& p : points) {
        const std::string name =
            "queries/" + std::string(scene_name) + "/" + p.name + "/" + how + "/threads:1";
        benchmark::RegisterBenchmark(
            name.c_str(),
            [=](benchmark::State& s) { run<Vec3>(s, scene_name, tree, p.query, p.reference); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }
  for (const int threads : {1, all_threads()}) {
    const std::string name =
        "queries/random:1048576/broad_phase/tree/threads:" + std::to_string(threads);
    benchmark::RegisterBenchmark(
        name.c_str(), [=](benchmark::State& s) { broad_phase(s, "random:1048576", threads); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Iterations(3);
  }
  register_crossing_benchmarks();
}

}  // namespace sphray::bench
