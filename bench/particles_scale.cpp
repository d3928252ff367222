// sphray_bench_particles: the phases before the first ray, on the spheres of one particle file
// (.sphp): reading it into a SphereSoA, and building sphray's tree and Embree's
// (rtcCommitScene, where built with Embree) over the same spheres, on one and on all threads.
// bench/particles_scale.sh runs it at 1M, 10M and 100M spheres beside `sphray render`'s own
// phases and peak memory, for docs/performance.md, "Particles at scale".
//
//   sphray_bench_particles --particles=FILE.sphp [Google Benchmark flags]
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "implementations.hpp"
#include "sphray/particles/particles.hpp"

namespace sphray::bench {
namespace {

void read_file(benchmark::State& state, const std::filesystem::path& file) {
  std::uint64_t count = 0;
  for (auto _ : state) {
    const particles::SphpFile in(file);  // opening and checking the header counts too
    SphereSoA spheres;
    spheres.reserve(in.count());
    in.read(0, in.count(), spheres);
    count = in.count();
    benchmark::DoNotOptimize(spheres.view().cx);
  }
  const auto bytes = particles::kSphpHeaderBytes + particles::kSphpRecordBytes * count;
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bytes));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(count));
  state.counters["spheres"] = static_cast<double>(count);
}

// The same read through a memory map, for comparison only: the library reads with pread
// (particles.hpp says why: a file truncated under a map kills the reader with SIGBUS). The
// records are copied into the SoA the same way, so the two rows differ in how bytes arrive.
void read_mapped(benchmark::State& state, const std::filesystem::path& file) {
  const std::uint64_t count = particles::SphpFile(file).count();  // the checked header
  const std::size_t bytes = particles::kSphpHeaderBytes + particles::kSphpRecordBytes * count;
  for (auto _ : state) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    void* map = ::mmap(nullptr, bytes, PROT_READ, MAP_PRIVATE, fd, 0);
    ::close(fd);
    if (map == MAP_FAILED) {
      state.SkipWithError("mmap failed");
      return;
    }
    ::madvise(map, bytes, MADV_SEQUENTIAL);
    const auto* record =
        static_cast<const float*>(map) + particles::kSphpHeaderBytes / sizeof(float);
    SphereSoA spheres;
    spheres.reserve(count);
    for (std::uint64_t i = 0; i < count; ++i, record += 4)  // little-endian hosts only
      spheres.add({record[0], record[1], record[2]}, record[3]);
    benchmark::DoNotOptimize(spheres.view().cx);
    ::munmap(map, bytes);
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bytes));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(count));
}

std::vector<Builder> tree_builders() {
  std::vector<Builder> all;
  for (Builder& b : bvh_builders())
    if (b.name == "bvh") all.push_back(std::move(b));  // refits are measured by sphray_bench
#if SPHRAY_BENCH_EMBREE
  for (Builder& b : embree_builders())
    all.push_back(std::move(b));
#endif
  return all;
}

// Takes --particles=FILE out of argv (Google Benchmark refuses flags it does not know).
std::string take_particles_flag(int& argc, char** argv) {
  constexpr std::string_view kFlag = "--particles=";
  std::string file;
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::string_view(argv[i]).starts_with(kFlag))
      file = argv[i] + kFlag.size();
    else
      argv[kept++] = argv[i];
  }
  argc = kept;
  return file;
}

}  // namespace
}  // namespace sphray::bench

int main(int argc, char** argv) {
  using namespace sphray::bench;
  const std::string file = take_particles_flag(argc, argv);
  if (file.empty()) {
    std::cerr << "usage: sphray_bench_particles --particles=FILE.sphp [benchmark flags]\n";
    return 2;
  }
  static sphray::SphereSoA spheres;
  try {
    spheres = sphray::particles::read_sphp(file);
  } catch (const sphray::particles::ParticleError& e) {
    std::cerr << "sphray_bench_particles: " << e.what() << "\n";
    return 2;
  }
  static const std::vector<Builder> builders = tree_builders();
  benchmark::RegisterBenchmark("particles/read", [file](benchmark::State& s) {
    read_file(s, file);
  })->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("particles/read_mapped", [file](benchmark::State& s) {
    read_mapped(s, file);
  })->Unit(benchmark::kMillisecond);
  for (const Builder& b : builders) {
    const std::string name = "particles/build/" + b.name + "/threads:" + std::to_string(b.threads);
    benchmark::RegisterBenchmark(name.c_str(),
                                 [&b](benchmark::State& s) { time_build(s, spheres, b); })
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::AddCustomContext("particles_file", file);
  benchmark::AddCustomContext("spheres", std::to_string(spheres.size()));
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
