#include "verify.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace sphray::bench {
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

}  // namespace

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

}  // namespace sphray::bench
