#include "bench/bench_agreement.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace sphray::render::bench {
namespace {

bool t_close(float a, float b) {
  return std::abs(a - b) <= kRelativeTolerance * std::max(1.0f, std::abs(b));
}

std::string describe(std::size_t i, const Ray& ray, const Hit& expected, const Hit& got) {
  std::ostringstream out;
  out << "ray " << i << " (origin " << ray.origin.x << ' ' << ray.origin.y << ' ' << ray.origin.z
      << ", dir " << ray.dir.x << ' ' << ray.dir.y << ' ' << ray.dir.z << "): reference id "
      << static_cast<long long>(expected.id == kNoHit ? -1 : expected.id) << " t " << expected.t
      << ", got id " << static_cast<long long>(got.id == kNoHit ? -1 : got.id) << " t " << got.t;
  return out.str();
}

// Whether some sphere's two roots lie within the tolerance of each other in the list.
bool grazes(const std::vector<Hit>& hits) {
  for (std::size_t i = 0; i < hits.size(); ++i)
    for (std::size_t j = i + 1; j < hits.size() && t_close(hits[j].t, hits[i].t); ++j)
      if (hits[j].id == hits[i].id) return true;
  return false;
}

// Whether sphere id crosses within the tolerance of t in the list.
bool crosses_near(const std::vector<Hit>& hits, std::uint32_t id, float t) {
  return std::any_of(hits.begin(), hits.end(),
                     [&](const Hit& h) { return h.id == id && t_close(h.t, t); });
}

std::string describe_crossings(std::size_t i, const Crossings& expected, const Crossings& got) {
  std::ostringstream out;
  out << "ray " << i << ": reference " << expected.total << " crossings, got " << got.total;
  const std::size_t n = std::min(expected.nearest.size(), got.nearest.size());
  for (std::size_t k = 0; k < n; ++k) {
    const Hit& e = expected.nearest[k];
    const Hit& g = got.nearest[k];
    if (e.id != g.id || !t_close(g.t, e.t)) {
      out << "; crossing " << k << ": reference id " << e.id << " t " << e.t << ", got id " << g.id
          << " t " << g.t;
      break;
    }
  }
  return out.str();
}

// The same total and, place by place, the same crossings up to ties (counted into ties).
bool lists_agree(const Crossings& e, const Crossings& g, std::size_t& ties) {
  if (e.total != g.total || e.nearest.size() != g.nearest.size()) return false;
  std::size_t found = 0;
  for (std::size_t k = 0; k < e.nearest.size(); ++k) {
    const Hit& eh = e.nearest[k];
    const Hit& gh = g.nearest[k];
    if (!t_close(gh.t, eh.t)) return false;
    if (eh.id == gh.id) continue;
    // Another sphere at the same t: it must cross there in the reference too, unless the tie
    // sits at the end of a full list, where the reference may have kept the other one.
    const bool at_cut = e.total > e.nearest.size() && t_close(gh.t, e.nearest.back().t);
    if (!crosses_near(e.nearest, gh.id, gh.t) && !at_cut) return false;
    ++found;
  }
  ties += found;
  return true;
}

}  // namespace

Agreement compare_crossings(std::span<const Crossings> expected, std::span<const Crossings> got) {
  Agreement a;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const Crossings& e = expected[i];
    const Crossings& g = got[i];
    if (e.total != g.total && (grazes(e.nearest) || grazes(g.nearest))) {
      ++a.undecided;
      continue;
    }
    ++a.compared;
    if (!lists_agree(e, g, a.id_ties) && a.first_mismatch.empty()) {
      a.first_mismatch = describe_crossings(i, e, g);
      a.mismatch_at = i;
    }
  }
  return a;
}

Agreement compare_hits(std::span<const Ray> rays, std::span<const Hit> expected,
                       std::span<const Hit> got) {
  Agreement a;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit& e = expected[i];
    const Hit& g = got[i];
    ++a.compared;
    if (!e.found() && !g.found()) continue;
    const bool agree = e.found() && g.found() && t_close(g.t, e.t);
    if (agree && e.id == g.id) continue;
    if (agree) {
      ++a.id_ties;
      continue;
    }
    if (a.first_mismatch.empty()) a.first_mismatch = describe(i, rays[i], e, g);
  }
  return a;
}

}  // namespace sphray::render::bench
