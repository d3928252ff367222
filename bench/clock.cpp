// Clock and instruction-throughput benchmarks: what turns time stamp counter ticks into core
// cycles, and the divider figures bench/count_loop.py's bound assumes, measured here.
#include <algorithm>
#include <cstdint>

#include <benchmark/benchmark.h>

#include "implementations.hpp"

namespace sphray::bench {
namespace {

#if defined(__x86_64__)

constexpr std::int64_t kLoopsPerSample = 4096;

// TSC ticks per call of body(): the fastest of many short samples, so a sample in which the
// thread was descheduled (the machine may be shared) does not count.
template <class Body>
double tsc_per_loop(benchmark::State& state, Body body) {
  std::uint64_t best = UINT64_MAX;
  for (auto _ : state) {
    const std::uint64_t start = __builtin_ia32_rdtsc();
    for (std::int64_t i = 0; i < kLoopsPerSample; ++i)
      body();
    best = std::min<std::uint64_t>(best, __builtin_ia32_rdtsc() - start);
  }
  return static_cast<double>(best) / static_cast<double>(kLoopsPerSample);
}

// A chain of dependent 64-bit multiplies, 3 cycles each on Intel cores since Nehalem and AMD
// cores since Zen. (A chain of adds would not do: recent Intel cores fold dependent
// immediate adds at rename.)
void core_clock(benchmark::State& state) {
  std::uint64_t x = 3;
  const double tsc = tsc_per_loop(state, [&] {
    asm volatile(
        "imul %0, %0\n\timul %0, %0\n\timul %0, %0\n\timul %0, %0\n\t"
        "imul %0, %0\n\timul %0, %0\n\timul %0, %0\n\timul %0, %0"
        : "+r"(x));
  });
  benchmark::DoNotOptimize(x);
  constexpr double kCyclesPerLoop = 8 * 3;
  state.counters["core_cycles_per_tsc_tick"] = kCyclesPerLoop / tsc;
}

// Eight independent square roots or divides per loop: their throughput, not their latency.
#define SPHRAY_EIGHT(op, src, r)                                                                  \
  op " " src ", %%" r "0\n\t" op " " src ", %%" r "1\n\t" op " " src ", %%" r "2\n\t" op " " src  \
     ", %%" r "3\n\t" op " " src ", %%" r "4\n\t" op " " src ", %%" r "5\n\t" op " " src ", %%" r \
     "6\n\t" op " " src ", %%" r "7\n\t"

// A normal input: denormal or NaN operands could take a slow microcode path.
constexpr float kTwo = 2.0f;

// The vector registers the loops below write.
#define SPHRAY_CLOBBERS \
  "xmm0", "xmm1", "xmm2", "xmm3", "xmm4", "xmm5", "xmm6", "xmm7", "xmm8", "xmm9"

// Times loop, eight of one instruction, if the processor has its instruction set, and reports
// TSC ticks per instruction.
template <class Loop>
void time_eight(benchmark::State& state, bool supported, const char* missing, Loop loop) {
  if (!supported) return state.SkipWithError(missing);
  const double tsc = tsc_per_loop(state, loop);
  asm volatile("vzeroupper");
  state.counters["tsc_per_instruction"] = tsc / 8;
}

void vsqrtps_ymm(benchmark::State& state) {
  time_eight(state, __builtin_cpu_supports("avx"), "no AVX", [] {
    asm volatile("vbroadcastss %0, %%ymm8\n\t" SPHRAY_EIGHT("vsqrtps", "%%ymm8", "ymm")
                 :
                 : "m"(kTwo)
                 : SPHRAY_CLOBBERS);
  });
}

void vdivps_ymm(benchmark::State& state) {
  time_eight(state, __builtin_cpu_supports("avx"), "no AVX", [] {
    asm volatile("vbroadcastss %0, %%ymm8\n\tvbroadcastss %0, %%ymm9\n\t" SPHRAY_EIGHT(
                     "vdivps", "%%ymm8, %%ymm9", "ymm")
                 :
                 : "m"(kTwo)
                 : SPHRAY_CLOBBERS);
  });
}

void vsqrtps_zmm(benchmark::State& state) {
  time_eight(state, __builtin_cpu_supports("avx512f"), "no AVX-512", [] {
    asm volatile("vbroadcastss %0, %%zmm8\n\t" SPHRAY_EIGHT("vsqrtps", "%%zmm8", "zmm")
                 :
                 : "m"(kTwo)
                 : SPHRAY_CLOBBERS);
  });
}

void vdivps_zmm(benchmark::State& state) {
  time_eight(state, __builtin_cpu_supports("avx512f"), "no AVX-512", [] {
    asm volatile("vbroadcastss %0, %%zmm8\n\tvbroadcastss %0, %%zmm9\n\t" SPHRAY_EIGHT(
                     "vdivps", "%%zmm8, %%zmm9", "zmm")
                 :
                 : "m"(kTwo)
                 : SPHRAY_CLOBBERS);
  });
}

#endif

}  // namespace

void register_clock_benchmarks() {
#if defined(__x86_64__)
  benchmark::RegisterBenchmark("clock/core", core_clock)->UseRealTime();
  benchmark::RegisterBenchmark("clock/vsqrtps-ymm", vsqrtps_ymm)->UseRealTime();
  benchmark::RegisterBenchmark("clock/vdivps-ymm", vdivps_ymm)->UseRealTime();
  benchmark::RegisterBenchmark("clock/vsqrtps-zmm", vsqrtps_zmm)->UseRealTime();
  benchmark::RegisterBenchmark("clock/vdivps-zmm", vdivps_zmm)->UseRealTime();
#endif
}

}  // namespace sphray::bench
