#include "bench/bench_timing.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <span>
#include <sstream>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace sphray::render::bench {
namespace {

bool agrees(const Hit& expected, const Hit& got, bool exact) {
  if (exact) return expected.id == got.id && (expected.t == got.t || !expected.found());
  if (!expected.found() || !got.found()) return expected.found() == got.found();
  return std::abs(expected.t - got.t) <= 1e-3f * std::max(1.0f, std::abs(expected.t));
}

std::string describe(const Ray& ray, const Hit& expected, const Hit& got) {
  auto id = [](const Hit& h) { return h.found() ? std::to_string(h.id) : std::string("none"); };
  std::ostringstream out;
  out << "ray from (" << ray.origin.x << ", " << ray.origin.y << ", " << ray.origin.z
      << ") towards (" << ray.dir.x << ", " << ray.dir.y << ", " << ray.dir.z
      << "): the scalar reference hits " << id(expected) << " at t " << expected.t << ", got "
      << id(got) << " at t " << got.t;
  return out.str();
}

std::string first_mismatch(const Row& row, const Trace& trace, const RaySet& set) {
  std::vector<Hit> got(set.sample.size());
  trace(set.sample, got);
  for (std::size_t i = 0; i < got.size(); ++i)
    if (!agrees(set.expected[i], got[i], row.exact))
      return describe(set.sample[i], set.expected[i], got[i]);
  return {};
}

double cpu_now() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::vector<double> wall_rates(const RowTiming& t) {
  std::vector<double> rates;
  for (const Timing& r : t.repetitions)
    rates.push_back(r.rays_per_second());
  return rates;
}

}  // namespace

double RowTiming::median_rate() const {
  return median(wall_rates(*this));
}

double RowTiming::min_rate() const {
  const std::vector<double> rates = wall_rates(*this);
  return rates.empty() ? 0.0 : *std::min_element(rates.begin(), rates.end());
}

double RowTiming::max_rate() const {
  const std::vector<double> rates = wall_rates(*this);
  return rates.empty() ? 0.0 : *std::max_element(rates.begin(), rates.end());
}

double RowTiming::median_cpu_rate() const {
  std::vector<double> rates;
  for (const Timing& r : repetitions)
    if (r.cpu_seconds > 0)
      rates.push_back(static_cast<double>(r.passes * r.rays_per_pass) * threads / r.cpu_seconds);
  return median(rates);
}

double RowTiming::cpu_share() const {
  double wall = 0.0, cpu = 0.0;
  for (const Timing& r : repetitions) {
    wall += r.seconds;
    cpu += r.cpu_seconds;
  }
  return wall > 0 ? cpu / (wall * threads) : 1.0;
}

RowTiming time_passes(std::size_t rays, const Answer& answer, int threads, double seconds,
                      int repetitions) {
  RowTiming timing;
  timing.threads = threads;
  // About 16 chunks per thread keeps every thread busy to the end when rays differ in cost.
  const std::size_t grain =
      std::clamp<std::size_t>(rays / (16 * static_cast<std::size_t>(threads)), 64, 4096);
  tbb::task_arena arena(threads);
  auto pass = [&] {
    if (threads == 1) return answer(0, rays);
    arena.execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, rays, grain),
          [&](const tbb::blocked_range<std::size_t>& r) { answer(r.begin(), r.end()); });
    });
  };
  pass();  // warm-up: caches, page faults, the arena's threads
  using Clock = std::chrono::steady_clock;
  const double share = seconds / std::max(1, repetitions);
  for (int i = 0; i < repetitions; ++i) {
    Timing t;
    const double cpu_start = cpu_now();
    const Clock::time_point start = Clock::now();
    do {
      pass();
      ++t.passes;
      t.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    } while (t.seconds < share);
    t.cpu_seconds = cpu_now() - cpu_start;
    t.rays_per_pass = rays;
    timing.repetitions.push_back(t);
  }
  return timing;
}

RowTiming time_row(const Row& row, const Trace& trace, const RaySet& set, int threads,
                   double seconds, int repetitions) {
  const std::string mismatch = first_mismatch(row, trace, set);
  if (!mismatch.empty()) {
    RowTiming timing;
    timing.mismatch = mismatch;
    return timing;
  }
  const std::vector<Ray>& rays = row.brute_force ? set.brute_rays : set.rays;
  std::vector<Hit> hits(rays.size());
  const std::span<const Ray> all_rays(rays);
  const std::span<Hit> all_hits(hits);
  return time_passes(
      rays.size(),
      [&](std::size_t begin, std::size_t end) {
        trace(all_rays.subspan(begin, end - begin), all_hits.subspan(begin, end - begin));
      },
      threads, seconds, repetitions);
}

}  // namespace sphray::render::bench
