#include "bench_json.hpp"

#include <unistd.h>

#include <ctime>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench_rows.hpp"
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
  return j;
}

nlohmann::json result_json(const Result& r, std::size_t index, int threads) {
  const Timing& t = r.timing;
  const double passes = static_cast<double>(t.passes);
  nlohmann::json j;
  j["name"] = r.name;
  j["family_index"] = index;
  j["per_family_instance_index"] = 0;
  j["run_name"] = r.name;
  j["run_type"] = "iteration";
  j["repetitions"] = 1;
  j["repetition_index"] = 0;
  j["threads"] = threads;
  j["iterations"] = t.passes;
  j["real_time"] = 1e3 * t.seconds / passes;  // per pass over the rays
  j["cpu_time"] = 1e3 * t.cpu_seconds / passes;
  j["time_unit"] = "ms";
  j["items_per_second"] = t.rays_per_second();
  j["rays"] = t.rays_per_pass;
  if (!r.label.empty()) j["label"] = r.label;
  return j;
}

}  // namespace

std::string results_json(const Context& context, const std::vector<Result>& results) {
  nlohmann::json j;
  j["context"] = context_json(context);
  j["benchmarks"] = nlohmann::json::array();
  for (std::size_t i = 0; i < results.size(); ++i)
    j["benchmarks"].push_back(result_json(results[i], i, context.threads));
  return j.dump(2) + "\n";
}

}  // namespace sphray::render::bench
