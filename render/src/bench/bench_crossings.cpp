#include "bench/bench_crossings.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <utility>

#include "bench/bench_agreement.hpp"
#include "bench/tree_cache.hpp"

namespace sphray::render::bench {
namespace {

// Each ray's crossings as trace gives them, lists cut to what it kept.
std::vector<Crossings> crossings_of(const CrossingRow& row, const CrossingTrace& trace,
                                    std::span<const Ray> rays) {
  std::vector<std::size_t> totals(rays.size());
  std::vector<Hit> lists(row.counts_only ? 0 : rays.size() * kCrossingRoom);
  trace(rays, totals, lists);
  std::vector<Crossings> out(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    out[i].total = totals[i];
    if (row.counts_only) continue;
    const auto first = lists.begin() + static_cast<std::ptrdiff_t>(i * kCrossingRoom);
    out[i].nearest.assign(first,
                          first + static_cast<std::ptrdiff_t>(std::min(totals[i], kCrossingRoom)));
  }
  return out;
}

// What the row owes of the full answer: no list for a counting row, and how many it kept, not
// the total, for the nearest alone.
void as_the_row_answers(const CrossingRow& row, std::vector<Crossings>& expected) {
  for (Crossings& c : expected) {
    if (row.counts_only) c.nearest.clear();
    if (row.kept_only) c.total = c.nearest.size();
  }
}

// Whether float arithmetic cannot settle some crossing of the ray to the comparison's
// tolerance, so that two libraries' roundings may answer differently and both be right to
// float's precision: a sphere's discriminant within its rounding of 0 (the ray grazes it:
// whether it crosses at all is rounding's call), or a root that rounding moves by more than a
// quarter of the tolerance (a ray meeting a sphere of radius 1000 at a shallow angle: the
// discriminant, a difference of terms of 10^6, keeps few bits, and the roots move by 10^-3
// relative), or a root within the tolerance of tmin. In double, over every sphere: only for the
// rare ray whose answers differ.
bool float_cannot_tell(SphereView spheres, const Ray& ray) {
  constexpr double kEpsilon = 0x1p-24;
  const double dx = ray.dir.x, dy = ray.dir.y, dz = ray.dir.z;
  const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
  for (std::size_t i = 0; i < spheres.count; ++i) {
    const double ox = spheres.cx[i] - double{ray.origin.x},
                 oy = spheres.cy[i] - double{ray.origin.y},
                 oz = spheres.cz[i] - double{ray.origin.z}, r = spheres.radius[i];
    const double oo = ox * ox + oy * oy + oz * oz;
    const double tca = (ox * dx + oy * dy + oz * dz) / length;  // along the unit direction
    const double h2 = r * r - (oo - tca * tca);                 // the half chord, squared
    const double rounding = 4 * kEpsilon * (oo + r * r);
    if (h2 < -rounding) continue;  // a clear miss
    if (h2 <= rounding) return true;
    const double h = std::sqrt(h2), moved = rounding / (2 * h) / length;
    for (const double t : {(tca - h) / length, (tca + h) / length}) {
      const double tolerance = kRelativeTolerance * std::max(1.0, std::abs(t));
      if (moved > tolerance / 4 || std::abs(t - ray.tmin) <= tolerance) return true;
    }
  }
  return false;
}

void add(CrossingCheck& check, const Agreement& a) {
  check.rays += a.compared + a.undecided;
  check.undecided += a.undecided;
  check.ties += a.id_ties;
  if (check.mismatch.empty()) check.mismatch = a.first_mismatch;
}

}  // namespace

std::vector<CrossingRow> sphray_crossing_rows() {
  auto shared = std::make_shared<TreeCache>();  // the default tree, for every row
  CrossingRow count{"tree count_hits", true, false, true, {}, {}, {}};
  count.prepare = [shared](SphereView spheres) -> CrossingTrace {
    return [tree = shared->get(spheres)](std::span<const Ray> rays, std::span<std::size_t> totals,
                                         std::span<Hit>) { count_hits(*tree, rays, totals); };
  };
  CrossingRow all{"tree intersect_all16", false, false, true, {}, {}, {}, true};
  all.prepare = [shared](SphereView spheres) -> CrossingTrace {
    return [tree = shared->get(spheres)](std::span<const Ray> rays, std::span<std::size_t> totals,
                                         std::span<Hit> lists) {
      intersect_all(*tree, rays, lists, kCrossingRoom, totals);
    };
  };
  CrossingRow nearest{"tree intersect_nearest16", false, true, true, {}, {}, {}};
  nearest.prepare = [shared](SphereView spheres) -> CrossingTrace {
    return [tree = shared->get(spheres)](std::span<const Ray> rays, std::span<std::size_t> totals,
                                         std::span<Hit> lists) {
      intersect_nearest(*tree, rays, lists, kCrossingRoom, totals);
    };
  };
  return {std::move(count), std::move(all), std::move(nearest)};
}

CrossingCheck check_crossing_row(const CrossingRow& row, const CrossingTrace& trace,
                                 const RaySet& set, SphereView spheres,
                                 const CrossingTrace& reference) {
  CrossingCheck check;
  if (row.sphray) {
    std::vector<Crossings> expected(set.sample.size());
    for (std::size_t i = 0; i < set.sample.size(); ++i) {
      expected[i].nearest.resize(kCrossingRoom);
      expected[i].total = scalar::intersect_all(spheres, set.sample[i], expected[i].nearest, {});
      expected[i].nearest.resize(std::min(expected[i].total, kCrossingRoom));
    }
    as_the_row_answers(row, expected);
    add(check, compare_crossings(expected, crossings_of(row, trace, set.sample)));
    return check;
  }
  // Every ray, a chunk at a time so that the lists stay small.
  const CrossingRow listing{"reference", false, false, true, {}, {}, {}};
  const std::span<const Ray> rays(set.rays);
  constexpr std::size_t kChunk = 4096;
  for (std::size_t first = 0; first < rays.size(); first += kChunk) {
    const std::span<const Ray> chunk = rays.subspan(first, std::min(kChunk, rays.size() - first));
    std::vector<Crossings> expected = crossings_of(listing, reference, chunk);
    std::vector<Crossings> got = crossings_of(row, trace, chunk);
    as_the_row_answers(row, expected);
    // A ray whose crossings float cannot settle is left to rounding, whichever way the lists
    // differ (a counting row has no list in which to see a graze): the spheres are asked.
    std::size_t grazing = 0;
    for (std::size_t i = 0; i < chunk.size(); ++i)
      if (!compare_crossings(std::span(&expected[i], 1), std::span(&got[i], 1)).ok() &&
          float_cannot_tell(spheres, chunk[i])) {
        got[i] = expected[i];
        ++grazing;
      }
    Agreement a = compare_crossings(expected, got);
    a.undecided += grazing;
    a.compared -= grazing;
    if (!a.ok()) {
      const Ray& ray = chunk[a.mismatch_at];
      std::ostringstream where;
      where.precision(9);
      where << "in the chunk from ray " << first << ", " << a.first_mismatch << " (origin "
            << ray.origin.x << ' ' << ray.origin.y << ' ' << ray.origin.z << ", direction "
            << ray.dir.x << ' ' << ray.dir.y << ' ' << ray.dir.z << ", tmin " << ray.tmin << ")";
      a.first_mismatch = where.str();
    }
    add(check, a);
    if (!check.mismatch.empty()) break;
  }
  return check;
}

RowTiming time_crossing_row(const CrossingRow& row, const CrossingTrace& trace, const RaySet& set,
                            int threads, double seconds, int repetitions) {
  const std::span<const Ray> rays(set.rays);
  std::vector<std::size_t> totals(rays.size());
  return time_passes(
      rays.size(),
      [&](std::size_t begin, std::size_t end) {
        // Each thread's lists for a chunk of rays: the answers are checked, not kept.
        thread_local std::vector<Hit> lists;
        lists.resize(row.counts_only ? 0 : (end - begin) * kCrossingRoom);
        trace(rays.subspan(begin, end - begin),
              std::span<std::size_t>(totals).subspan(begin, end - begin), lists);
      },
      threads, seconds, repetitions);
}

}  // namespace sphray::render::bench
