#include "bench/bench_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <thread>
#include <vector>

#include "bench/bench_crossings.hpp"
#include "bench/bench_json.hpp"
#include "bench/bench_rays.hpp"
#include "bench/bench_report.hpp"
#include "bench/bench_rows.hpp"
#include "bench/bench_timing.hpp"
#include "command/command_failure.hpp"
#include "command/progress_report.hpp"
#include "image/atomic_output.hpp"
#include "sphray/render/image_file.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render::bench {
namespace {

std::vector<RayKind> ray_kinds(const std::string& rays) {
  if (rays == "camera") return {RayKind::camera};
  if (rays == "random") return {RayKind::random};
  return {RayKind::camera, RayKind::random};
}

std::string mrays(double per_second) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", per_second / 1e6);
  return text;
}

std::string result_name(const Context& c, RayKind kind, const std::string& row_name) {
  std::string name = row_name;
  for (char& ch : name)
    if (ch == ' ') ch = '-';
  return c.scene + "/" + ray_kind_name(kind) + "/" + name + "/threads:" + std::to_string(c.threads);
}

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A transient line on a terminal's stderr while a row runs: which row of how many, what it is
// doing, the time so far and the time left (by the rows done so far, the estimate before).
class Progress {
 public:
  Progress(bool enabled, std::size_t rows, double estimate)
      : enabled_(enabled && ::isatty(STDERR_FILENO)), rows_(rows), estimate_(estimate) {}
  void show(const std::string& text) const {
    if (!enabled_) return;
    const double elapsed = seconds_since(start_);
    const double left =
        done_ > 0 ? elapsed / static_cast<double>(done_) * static_cast<double>(rows_ - done_)
                  : std::max(0.0, estimate_ - elapsed);
    std::fprintf(stderr, "\r\033[K  [%zu/%zu] %s ... %s elapsed, about %s left", done_ + 1, rows_,
                 text.c_str(), progress::duration_text(elapsed).c_str(),
                 progress::duration_text(left).c_str());
  }
  void row_done() { ++done_; }
  void clear() const {
    if (enabled_) std::fputs("\r\033[K", stderr);
  }

 private:
  bool enabled_;
  std::size_t rows_, done_ = 0;
  double estimate_;
  Clock::time_point start_ = Clock::now();
};

void print_header(const Context& c) {
  const std::string isas = supported_isa_list();
  std::printf("sphray bench: %s, %zu spheres, %d thread%s, %.2g s per row in %d repetition%s\n",
              c.scene.c_str(), c.spheres, c.threads, c.threads == 1 ? "" : "s", c.seconds_per_row,
              c.repetitions, c.repetitions == 1 ? "" : "s");
  std::printf("instruction sets: %s; queries: %s, trees: %s (* marks the rows they take)\n",
              isas.c_str(), std::string(isa_name(active_isa())).c_str(),
              std::string(isa_name(bvh_isa(c.spheres))).c_str());
  const std::string embree = embree_version();
  std::printf("%s\n", embree.empty() ? "Embree: not in this build" : embree.c_str());
}

// A note after a row's rates, and for a row whose threads did not have their cores all the
// time, how much they had; indented, or empty.
std::string with_cpu_share(std::string text, const RowTiming& timing) {
  if (timing.cpu_share() < 0.9) {
    char part[64];
    std::snprintf(part, sizeof part, "%shad the CPU %.0f%% of the time", text.empty() ? "" : "; ",
                  100 * timing.cpu_share());
    text += part;
  }
  return text.empty() ? text : "  " + text;
}

// After a row's rates: for another library's row, how sphray's default tree compares; for a row
// whose threads did not have their cores all the time, how much they had.
std::string note(const Row& row, const RowTiming& timing, double tree_rate) {
  std::string text;
  char part[96];
  if (!row.exact && tree_rate > 0) {
    const double ratio = tree_rate / timing.median_rate();
    if (ratio >= 1)
      std::snprintf(part, sizeof part, "sphray's default tree (*) is %.2fx as fast", ratio);
    else
      std::snprintf(part, sizeof part, "%.2fx as fast as sphray's default tree (*)", 1 / ratio);
    text += part;
  }
  return with_cpu_share(text, timing);
}

void print_table_header() {
  std::printf("  %-25s %8s  %-13s  %11s\n", "row", "Mrays/s", "(min-max)", "by CPU time");
}

// A row's rates on one line: the median, the spread and the rate by CPU time, then a note.
void print_rates(const std::string& name, bool dispatched, const RowTiming& timing,
                 const std::string& note) {
  char spread[48];
  std::snprintf(spread, sizeof spread, "(%.2f-%.2f)", timing.min_rate() / 1e6,
                timing.max_rate() / 1e6);
  std::printf("  %-24s%s %8s  %-13s  %11s%s\n", name.c_str(), dispatched ? "*" : " ",
              mrays(timing.median_rate()).c_str(), spread, mrays(timing.median_cpu_rate()).c_str(),
              note.c_str());
  std::fflush(stdout);
}

// The rows of one ray kind, printed as they finish; false at the first disagreement.
bool run_kind(const BenchArgs& args, const Scene& scene, const Context& context, RayKind kind,
              const std::vector<Row>& rows, Progress& progress, std::vector<Result>& results,
              std::vector<Measured>& measured) {
  progress.show(std::string("making ") + ray_kind_name(kind) + " rays");
  const RaySet set = make_ray_set(scene, kind);
  progress.clear();
  std::printf("\n%s rays (%s", ray_kind_name(kind), set.description.c_str());
  if (kind == RayKind::camera) std::printf(", %zu rays", set.rays.size());
  const bool brute_timed = std::any_of(
      rows.begin(), rows.end(), [](const Row& r) { return r.brute_force && r.skipped.empty(); });
  if (brute_timed && set.brute_rays.size() < set.rays.size())
    std::printf("; brute force traces %zu of them, spread evenly, to keep a pass short",
                set.brute_rays.size());
  std::printf("):\n");
  print_table_header();
  std::fflush(stdout);
  double tree_rate = 0.0;  // the dispatched tree's, for the ratios of the Embree rows
  for (const Row& row : rows) {
    if (!row.skipped.empty()) {
      std::printf("  %-25s skipped: %s\n", row.name.c_str(), row.skipped.c_str());
      results.push_back({result_name(context, kind, row.name), "", {}, row.skipped});
      continue;
    }
    progress.show(row.name + ": " + (row.brute_force ? "checking" : "building, checking"));
    RowTiming timing;
    {
      const Trace trace = row.prepare(scene.spheres.view());  // released before the next row
      progress.show(row.name + ": timing");
      timing = time_row(row, trace, set, args.threads, args.seconds, args.repetitions);
    }
    progress.row_done();
    progress.clear();
    if (!timing.mismatch.empty()) {
      std::fprintf(stderr, "sphray: %s disagrees with the scalar reference on %s rays: %s\n",
                   row.name.c_str(), ray_kind_name(kind), timing.mismatch.c_str());
      return false;
    }
    const double r = timing.median_rate();
    if (row.dispatched && row.name.ends_with(" tree")) tree_rate = r;
    print_rates(row.name, row.dispatched, timing, note(row, timing, tree_rate));
    measured.push_back({row.name, row.dispatched, row.brute_force, row.name.ends_with(" stream"),
                        row.exact, r, timing.min_rate(), timing.max_rate()});
    results.push_back({result_name(context, kind, row.name), row.dispatched ? "dispatched" : "",
                       std::move(timing), ""});
  }
  return true;
}

// After an every-hit row's rates: for another library's row, how sphray's row with the same
// answer compares, and how many rays the check compared; as note() for the CPU share.
std::string crossing_note(const CrossingRow& row, const CrossingCheck& check,
                          const RowTiming& timing, double same_answer_rate) {
  std::string text;
  char part[160];
  if (!row.sphray && same_answer_rate > 0) {
    std::snprintf(part, sizeof part,
                  "%s is %.2fx as fast; checked on all %zu rays: %zu undecided, %zu ties",
                  row.same_answer_as.c_str(), same_answer_rate / timing.median_rate(), check.rays,
                  check.undecided, check.ties);
    text += part;
  }
  return with_cpu_share(text, timing);
}

// The every-hit rows of one ray kind (--query every-hit), printed as they finish; false at the
// first disagreement. sphray's intersect_all16 row is the reference another library's rows are
// checked against, on every ray.
bool run_every_hit_kind(const BenchArgs& args, const Scene& scene, const Context& context,
                        RayKind kind, const std::vector<CrossingRow>& rows, Progress& progress,
                        std::vector<Result>& results) {
  progress.show(std::string("making ") + ray_kind_name(kind) + " rays");
  const RaySet set = make_ray_set(scene, kind);
  progress.clear();
  std::printf("\n%s rays (%s, %zu rays), every crossing:\n", ray_kind_name(kind),
              set.description.c_str(), set.rays.size());
  print_table_header();
  const SphereView spheres = scene.spheres.view();
  const CrossingTrace reference = std::find_if(rows.begin(), rows.end(), [](const CrossingRow& r) {
                                    return r.reference;
                                  })->prepare(spheres);
  std::vector<std::pair<std::string, double>> rates;  // sphray's rows, for the ratios
  for (const CrossingRow& row : rows) {
    if (!row.skipped.empty()) {
      std::printf("  %-25s skipped: %s\n", row.name.c_str(), row.skipped.c_str());
      results.push_back({result_name(context, kind, row.name), "", {}, row.skipped});
      continue;
    }
    progress.show(row.name + ": checking");
    const CrossingTrace trace = row.prepare(spheres);
    const CrossingCheck check = check_crossing_row(row, trace, set, spheres, reference);
    if (!check.mismatch.empty()) {
      progress.clear();
      std::fprintf(stderr, "sphray: %s disagrees with %s on %s rays: %s\n", row.name.c_str(),
                   row.sphray ? "the scalar reference" : "sphray's intersect_all16",
                   ray_kind_name(kind), check.mismatch.c_str());
      return false;
    }
    progress.show(row.name + ": timing");
    RowTiming timing =
        time_crossing_row(row, trace, set, args.threads, args.seconds, args.repetitions);
    progress.row_done();
    progress.clear();
    double same_answer_rate = 0;
    for (const auto& [name, rate] : rates)
      if (name == row.same_answer_as) same_answer_rate = rate;
    if (row.sphray) rates.emplace_back(row.name, timing.median_rate());
    print_rates(row.name, false, timing, crossing_note(row, check, timing, same_answer_rate));
    results.push_back({result_name(context, kind, row.name), "", std::move(timing), ""});
  }
  return true;
}

// The JSON file's temporary, made before any row is timed: a path that cannot or may not be
// written is refused at once rather than after the whole run, and an existing file is only
// ever replaced whole (docs/robustness.md, "The output file"). Null without --json; prints the
// refusal and sets status otherwise.
std::unique_ptr<detail::AtomicOutput> open_json(const BenchArgs& args, int& status) {
  status = 0;
  if (args.json.empty()) return nullptr;
  try {
    return std::make_unique<detail::AtomicOutput>(args.json, args.force);
  } catch (const std::exception&) {  // a refusal (exit 2) or an I/O error (exit 1)
    status = report_failure("out of memory opening the JSON file");
  }
  return nullptr;
}

bool write_json(detail::AtomicOutput& out, const Context& context,
                const std::vector<Result>& results) {
  try {
    const std::string text = results_json(context, results);
    out.write(text.data(), text.size());
    out.commit();
    return true;
  } catch (const IoError& e) {
    report(e.what());
    return false;
  }
}

}  // namespace

int run_bench(const BenchArgs& args) {
  const Clock::time_point start = Clock::now();
  Scene scene;
  try {
    scene = load_scene_or_preset(args.scene);
    apply_camera(args.camera, scene);
  } catch (const SceneError&) {
    return report_failure("out of memory loading the scene");
  }
  int status = 0;
  const std::unique_ptr<detail::AtomicOutput> json = open_json(args, status);
  if (status != 0) return status;
  Context context{args.scene,   scene.spheres.size(), args.threads,
                  args.seconds, args.repetitions,     {}};
  double load[3];
  if (::getloadavg(load, 3) == 3) context.load_average.assign(load, load + 3);
  print_header(context);
  const bool every_hit = args.query == "every-hit";
  std::vector<Row> rows;
  std::vector<CrossingRow> crossing_rows;
  if (every_hit) {
    crossing_rows = sphray_crossing_rows();
    for (CrossingRow& row : embree_crossing_rows())
      crossing_rows.push_back(std::move(row));
  } else {
    rows = sphray_rows(scene.spheres.size());
    for (Row& row : embree_rows())
      rows.push_back(std::move(row));
  }
  const std::vector<RayKind> kinds = ray_kinds(args.rays);
  const auto timed = static_cast<std::size_t>(
      std::count_if(rows.begin(), rows.end(), [](const Row& r) { return r.skipped.empty(); }) +
      std::count_if(crossing_rows.begin(), crossing_rows.end(),
                    [](const CrossingRow& r) { return r.skipped.empty(); }));
  const double estimate = estimate_seconds(timed * kinds.size(), args.seconds);
  std::printf(
      "%zu rows to time (%zu per ray kind): about %s, longer where a pass over the rays or a "
      "tree's build is slow, or the machine is busy\n",
      timed * kinds.size(), timed, progress::duration_text(estimate).c_str());
  if (!context.load_average.empty()) {
    const std::string warning = load_warning(
        context.load_average[0], std::max(1u, std::thread::hardware_concurrency()), args.threads);
    if (!warning.empty()) std::printf("%s\n", warning.c_str());
  }
  std::fflush(stdout);
  Progress progress(!args.quiet, timed * kinds.size(), estimate);
  std::vector<Result> results;
  std::vector<std::vector<Measured>> measured(kinds.size());
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    const bool agreed =
        every_hit
            ? run_every_hit_kind(args, scene, context, kinds[k], crossing_rows, progress, results)
            : run_kind(args, scene, context, kinds[k], rows, progress, results, measured[k]);
    if (!agreed) return kExitIo;
  }
  std::printf("\n");
  for (std::size_t k = 0; k < kinds.size(); ++k)
    std::printf("%s", recommendation(measured[k], ray_kind_name(kinds[k])).c_str());
  std::printf("took %s in all (estimated: about %s)\n",
              progress::duration_text(seconds_since(start)).c_str(),
              progress::duration_text(estimate).c_str());
  std::fflush(stdout);
  if (json && !write_json(*json, context, results)) return kExitIo;
  return 0;
}

}  // namespace sphray::render::bench
