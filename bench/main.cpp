// sphray_bench: every implementation on every workload in one process, so the ratios between
// them come from one machine state. Run with --benchmark_out=FILE.json --benchmark_out_format=json
// and give that file to bench/report.py (bench/run.sh does both).
#include <fstream>
#include <string>

#include <benchmark/benchmark.h>

#include "implementations.hpp"
#include "threads.hpp"

#if SPHRAY_BENCH_EMBREE
#include <embree3/rtcore.h>
#endif

namespace sphray::bench {
namespace {

std::vector<Implementation> all_implementations() {
  std::vector<Implementation> impls = kernel_implementations();
  for (Implementation& impl : bvh_implementations())
    impls.push_back(std::move(impl));
#if SPHRAY_BENCH_EMBREE
  for (Implementation& impl : embree_implementations())
    impls.push_back(std::move(impl));
#endif
  return impls;
}

std::vector<Builder> all_builders() {
  std::vector<Builder> builders = bvh_builders();
#if SPHRAY_BENCH_EMBREE
  for (Builder& b : embree_builders())
    builders.push_back(std::move(b));
#endif
  return builders;
}

// The first line of /proc/cpuinfo starting with key, after its colon.
std::string cpuinfo(const std::string& key) {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(key, 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

void describe_machine() {
  benchmark::AddCustomContext("cpu_model", cpuinfo("model name"));
  benchmark::AddCustomContext("cpu_signature", cpuinfo("cpu family") + "/" + cpuinfo("model\t") +
                                                   "/" + cpuinfo("stepping"));
  benchmark::AddCustomContext("cpu_flags", cpuinfo("flags"));
  benchmark::AddCustomContext("threads_all", std::to_string(all_threads()));
  std::string isas;
  for (Isa isa : supported_isas()) {
    if (!isas.empty()) isas += ' ';
    isas += isa_name(isa);
  }
  benchmark::AddCustomContext("sphray_isas", isas);
  benchmark::AddCustomContext("sphray_active_isa", std::string(isa_name(active_isa())));
#if SPHRAY_BENCH_EMBREE
  benchmark::AddCustomContext("embree_version", RTC_VERSION_STRING);
#endif
}

}  // namespace
}  // namespace sphray::bench

int main(int argc, char** argv) {
  using namespace sphray::bench;
  // Registered benchmarks hold references to these: they live until exit.
  static const std::vector<Implementation> implementations = all_implementations();
  static const std::vector<Builder> builders = all_builders();
  register_clock_benchmarks();
  register_benchmarks(implementations, builders);
  register_query_benchmarks();
  register_shadow_benchmarks();
  register_double_benchmarks();
  describe_machine();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
