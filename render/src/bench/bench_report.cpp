#include "bench/bench_report.hpp"

#include <algorithm>
#include <cstdio>

namespace sphray::render::bench {
namespace {

std::string mrays(double per_second) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f Mrays/s", per_second / 1e6);
  return text;
}

// The call a user writes for a default row.
std::string call(const Measured& m) {
  if (m.brute_force && m.stream)
    return "the stream call on the spheres, sphray::intersect(spheres, rays, hits)";
  if (m.brute_force) return "brute force, sphray::intersect(spheres, ray)";
  if (m.stream) return "the stream call on a tree, sphray::intersect(tree, rays, hits)";
  return "one ray at a time on a tree, sphray::intersect(tree, ray)";
}

// "1.36x slower" or "1.03x slower, within the spread of the repetitions".
std::string slower(const Measured& best, const Measured& other) {
  char text[96];
  std::snprintf(text, sizeof text, "%.2fx slower%s", best.median / other.median,
                other.max >= best.min ? ", within the spread of the repetitions" : "");
  return text;
}

}  // namespace

double estimate_seconds(std::size_t timed_rows, double seconds_per_row) {
  return static_cast<double>(timed_rows) * seconds_per_row;
}

std::string load_warning(double load_1min, unsigned cores, int threads) {
  const double free_cores = static_cast<double>(cores) - static_cast<double>(threads);
  if (!(load_1min > free_cores + 0.5)) return {};
  char text[320];
  std::snprintf(text, sizeof text,
                "warning: the machine is busy (load average %.2f over the last minute, %u "
                "cores, this run needs %d): other work takes turns on the cores, so the rates "
                "by wall time come out low and uneven; the rates by CPU time are less affected. "
                "Measure on a quiet machine for figures to keep.",
                load_1min, cores, threads);
  return text;
}

std::string recommendation(const std::vector<Measured>& rows, const std::string& kind) {
  std::vector<Measured> defaults;
  for (const Measured& m : rows)
    if (m.sphray && m.dispatched && m.median > 0) defaults.push_back(m);
  if (defaults.empty()) return {};
  std::sort(defaults.begin(), defaults.end(),
            [](const Measured& a, const Measured& b) { return a.median > b.median; });
  const Measured& best = defaults.front();
  std::string text = "fastest for " + kind + " rays: " + call(best) + ", " + mrays(best.median) +
                     " (" + best.name + ")\n";
  for (std::size_t i = 1; i < defaults.size(); ++i)
    text += "  " + call(defaults[i]) + ": " + slower(best, defaults[i]) + "\n";
  // A tree laid out for another instruction set (SphereBVH(spheres, isa)), if it beat the
  // default beyond the spread of both.
  const Measured* other = nullptr;
  for (const Measured& m : rows)
    if (m.sphray && !m.dispatched && !m.brute_force && m.median > 0 &&
        (other == nullptr || m.median > other->median))
      other = &m;
  if (other != nullptr && other->min > best.max) {
    const std::string isa = other->name.substr(0, other->name.find(' '));
    std::string enumerator = isa;  // "sse4.2" is Isa::sse4_2
    std::replace(enumerator.begin(), enumerator.end(), '.', '_');
    char ratio[32];
    std::snprintf(ratio, sizeof ratio, "%.2fx", other->median / best.median);
    text += "  faster still here: a tree laid out for " + isa + " (" + other->name +
            "), built as SphereBVH(spheres, sphray::Isa::" + enumerator + "): " + ratio +
            " as fast\n";
  }
  return text;
}

}  // namespace sphray::render::bench
