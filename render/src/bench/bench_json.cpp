#include "bench/bench_json.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench/bench_rows.hpp"
#include "sphray/version.hpp"

namespace sphray::render::bench {
namespace {

std::string now_iso8601() {
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  char text[40];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S%z", &local);
  return text;
}

std::string host_name() {
  char name[256] = {};
  return ::gethostname(name, sizeof name - 1) == 0 ? name : "unknown";
}

nlohmann::json context_json(const Context& c) {
  nlohmann::json j;
  j["date"] = now_iso8601();
  j["host_name"] = host_name();
  j["executable"] = "sphray bench";
  j["num_cpus"] = std::thread::hardware_concurrency();
  j["library_build_type"] = "release";
  j["sphray_version"] = kVersion;
  j["sphray_isas"] = supported_isa_list();
  j["sphray_active_isa"] = std::string(isa_name(active_isa()));
  j["sphray_bvh_isa"] = std::string(isa_name(bvh_isa(c.spheres)));
  j["embree_version"] = embree_version();
  j["scene"] = c.scene;
  j["spheres"] = c.spheres;
  j["threads"] = c.threads;
  j["seconds_per_row"] = c.seconds_per_row;
  j["repetitions"] = c.repetitions;
  if (!c.load_average.empty()) j["load_avg"] = c.load_average;  // Google Benchmark's name
  return j;
}

nlohmann::json entry(const Result& r, std::size_t index, int threads, int repetitions) {
  nlohmann::json j;
  j["name"] = r.name;
  j["family_index"] = index;
  j["per_family_instance_index"] = 0;
  j["run_name"] = r.name;
  j["repetitions"] = repetitions;
  j["threads"] = threads;
  j["time_unit"] = "ms";
  if (!r.label.empty()) j["label"] = r.label;
  return j;
}

// One repetition, as Google Benchmark writes an iteration run.
nlohmann::json repetition_json(const Result& r, std::size_t index, int threads, int repetition) {
  const Timing& t = r.timing.repetitions[static_cast<std::size_t>(repetition)];
  const double passes = static_cast<double>(t.passes);
  nlohmann::json j = entry(r, index, threads, static_cast<int>(r.timing.repetitions.size()));
  j["run_type"] = "iteration";
  j["repetition_index"] = repetition;
  j["iterations"] = t.passes;
  j["real_time"] = 1e3 * t.seconds / passes;  // per pass over the rays
  j["cpu_time"] = 1e3 * t.cpu_seconds / passes;
  j["items_per_second"] = t.rays_per_second();
  j["rays"] = t.rays_per_pass;
  return j;
}

// The aggregates Google Benchmark adds after the repetitions (each field on its own, as it
// computes them), with min and max as user-defined statistics of the same layout.
void add_aggregates(const Result& r, std::size_t index, int threads, nlohmann::json& out) {
  const std::vector<Timing>& reps = r.timing.repetitions;
  std::vector<double> real, cpu, rate;
  for (const Timing& t : reps) {
    const double passes = static_cast<double>(t.passes);
    real.push_back(1e3 * t.seconds / passes);
    cpu.push_back(1e3 * t.cpu_seconds / passes);
    rate.push_back(t.rays_per_second());
  }
  using Statistic = double (*)(std::vector<double>);
  const std::pair<const char*, Statistic> statistics[] = {
      {"mean",
       [](std::vector<double> v) {
         double sum = 0;
         for (double x : v)
           sum += x;
         return sum / static_cast<double>(v.size());
       }},
      {"median",
       [](std::vector<double> v) {
         std::sort(v.begin(), v.end());
         const std::size_t n = v.size();
         return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
       }},
      {"stddev",
       [](std::vector<double> v) {
         if (v.size() < 2) return 0.0;
         double sum = 0, squares = 0;
         for (double x : v)
           sum += x;
         const double mean = sum / static_cast<double>(v.size());
         for (double x : v)
           squares += (x - mean) * (x - mean);
         return std::sqrt(squares / static_cast<double>(v.size() - 1));
       }},
      {"min", [](std::vector<double> v) { return *std::min_element(v.begin(), v.end()); }},
      {"max", [](std::vector<double> v) { return *std::max_element(v.begin(), v.end()); }},
  };
  for (const auto& [name, statistic] : statistics) {
    nlohmann::json j = entry(r, index, threads, static_cast<int>(reps.size()));
    j["name"] = r.name + "_" + name;
    j["run_type"] = "aggregate";
    j["aggregate_name"] = name;
    j["aggregate_unit"] = "time";
    j["iterations"] = reps.size();
    j["real_time"] = statistic(real);
    j["cpu_time"] = statistic(cpu);
    j["items_per_second"] = statistic(rate);
    j["rays"] = reps.front().rays_per_pass;
    out.push_back(std::move(j));
  }
}

}  // namespace

std::string results_json(const Context& context, const std::vector<Result>& results) {
  nlohmann::json j;
  j["context"] = context_json(context);
  j["benchmarks"] = nlohmann::json::array();
  j["context"]["skipped"] = nlohmann::json::array();
  std::size_t family = 0;
  for (const Result& r : results) {
    if (!r.skipped.empty()) {
      j["context"]["skipped"].push_back({{"name", r.name}, {"reason", r.skipped}});
      continue;
    }
    const int repetitions = static_cast<int>(r.timing.repetitions.size());
    for (int i = 0; i < repetitions; ++i)
      j["benchmarks"].push_back(repetition_json(r, family, context.threads, i));
    if (repetitions > 1) add_aggregates(r, family, context.threads, j["benchmarks"]);
    ++family;
  }
  return j.dump(2) + "\n";
}

}  // namespace sphray::render::bench
