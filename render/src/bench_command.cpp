#include "bench_command.hpp"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <vector>

#include "bench_json.hpp"
#include "bench_rays.hpp"
#include "bench_rows.hpp"
#include "bench_timing.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render::bench {
namespace {

constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

std::vector<RayKind> ray_kinds(const std::string& rays) {
  if (rays == "camera") return {RayKind::camera};
  if (rays == "random") return {RayKind::random};
  return {RayKind::camera, RayKind::random};
}

std::string rate(double per_second) {
  char text[32];
  std::snprintf(text, sizeof text, "%9.2f Mrays/s", per_second / 1e6);
  return text;
}

std::string result_name(const Context& c, RayKind kind, const Row& row) {
  std::string name = row.name;
  for (char& ch : name)
    if (ch == ' ') ch = '-';
  return c.scene + "/" + ray_kind_name(kind) + "/" + name + "/threads:" + std::to_string(c.threads);
}

// A transient line on a terminal's stderr while a row runs (its check and its passes).
class Progress {
 public:
  explicit Progress(bool enabled) : enabled_(enabled && ::isatty(STDERR_FILENO)) {}
  void show(const std::string& text) const {
    if (enabled_) std::fprintf(stderr, "\r\033[K  %s ...", text.c_str());
  }
  void clear() const {
    if (enabled_) std::fputs("\r\033[K", stderr);
  }

 private:
  bool enabled_;
};

void print_header(const Context& c) {
  const std::string isas = supported_isa_list();
  std::printf("sphray bench: %s, %zu spheres, %d thread%s, %.2g s per row\n", c.scene.c_str(),
              c.spheres, c.threads, c.threads == 1 ? "" : "s", c.seconds_per_row);
  std::printf("instruction sets: %s; queries: %s, trees: %s (* marks the rows they take)\n",
              isas.c_str(), std::string(isa_name(active_isa())).c_str(),
              std::string(isa_name(bvh_isa(c.spheres))).c_str());
  const std::string embree = embree_version();
  std::printf("%s\n", embree.empty() ? "Embree: not in this build" : embree.c_str());
}

// After a row's rate: how many of the rays brute force traced, if not all; for another
// library's row, how the dispatched tree compares.
std::string note(const Row& row, const RaySet& set, const Timing& timing, double tree_rate) {
  char text[64] = "";
  if (row.brute_force && timing.rays_per_pass < set.rays.size())
    std::snprintf(text, sizeof text, "  (%zu of the rays)", timing.rays_per_pass);
  if (!row.exact && tree_rate > 0)
    std::snprintf(text, sizeof text, "  (tree* %.2fx this)", tree_rate / timing.rays_per_second());
  return text;
}

// The rows of one ray kind, printed as they finish; false at the first disagreement.
bool run_kind(const BenchArgs& args, const Scene& scene, const Context& context, RayKind kind,
              const std::vector<Row>& rows, std::vector<Result>& results) {
  const Progress progress(!args.quiet);
  progress.show(std::string("making ") + ray_kind_name(kind) + " rays");
  const RaySet set = make_ray_set(scene, kind);
  progress.clear();
  std::printf("\n%s rays (%s):\n", ray_kind_name(kind), set.description.c_str());
  std::fflush(stdout);
  double tree_rate = 0.0;  // the dispatched tree's, for the ratios of the Embree rows
  for (const Row& row : rows) {
    progress.show(row.name);
    Timing timing;
    {
      const Trace trace = row.prepare(scene.spheres.view());  // released before the next row
      timing = time_row(row, trace, set, args.threads, args.seconds);
    }
    progress.clear();
    if (!timing.mismatch.empty()) {
      std::fprintf(stderr, "sphray: %s disagrees with the scalar reference on %s rays: %s\n",
                   row.name.c_str(), ray_kind_name(kind), timing.mismatch.c_str());
      return false;
    }
    const double r = timing.rays_per_second();
    if (row.dispatched && row.name.ends_with(" tree")) tree_rate = r;
    std::printf("  %-24s%s%s%s\n", row.name.c_str(), row.dispatched ? "*" : " ", rate(r).c_str(),
                note(row, set, timing, tree_rate).c_str());
    std::fflush(stdout);
    results.push_back(
        {result_name(context, kind, row), row.dispatched ? "dispatched" : "", timing});
  }
  return true;
}

bool write_json(const std::string& path, const Context& context,
                const std::vector<Result>& results) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << results_json(context, results);
  out.close();
  if (out) return true;
  std::fprintf(stderr, "sphray: %s: cannot write the results\n", path.c_str());
  return false;
}

}  // namespace

int run_bench(const BenchArgs& args) {
  Scene scene;
  try {
    scene = load_scene_or_preset(args.scene);
  } catch (const SceneError& e) {
    std::fprintf(stderr, "sphray: %s\n", e.what());
    return kExitUsage;
  }
  const Context context{args.scene, scene.spheres.size(), args.threads, args.seconds};
  print_header(context);
  std::vector<Row> rows = sphray_rows(scene.spheres.size());
  for (Row& row : embree_rows())
    rows.push_back(std::move(row));
  std::vector<Result> results;
  for (RayKind kind : ray_kinds(args.rays))
    if (!run_kind(args, scene, context, kind, rows, results)) return kExitFailure;
  if (!args.json.empty() && !write_json(args.json, context, results)) return kExitFailure;
  return 0;
}

}  // namespace sphray::render::bench
