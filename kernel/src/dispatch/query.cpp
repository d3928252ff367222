// The public queries: each forwards to the kernel chosen at run time.
#include "sphray/query.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dispatch/entry_table.hpp"
#include "dispatch/query_plan.hpp"
#include "sphray/isa.hpp"

namespace sphray {

// Views below kScalarBelow spheres go straight to the scalar loop, as kernel_for_size() would
// send them: a ray against one sphere takes a few nanoseconds, and looking the kernel up measured
// a fifth of that.
Hit intersect(SphereView spheres, const Ray& ray) {
  if (detail::SPHRAY_ISA_NAMESPACE::QueryPlan::scalar(spheres.count))
    return scalar::intersect(spheres, ray);
  return detail::kernel_for_size(spheres.count).intersect(spheres, ray);
}

bool occluded(SphereView spheres, const Ray& ray) {
  if (detail::SPHRAY_ISA_NAMESPACE::QueryPlan::scalar(spheres.count))
    return scalar::occluded(spheres, ray);
  return detail::kernel_for_size(spheres.count).occluded(spheres, ray);
}

void intersect(SphereView spheres, std::span<const Ray> rays, std::span<Hit> hits) {
  if (rays.size() != hits.size())
    throw std::length_error("sphray::intersect: rays and hits differ in size");
  detail::kernel_for_size(spheres.count)
      .intersect_stream(spheres, rays.data(), hits.data(), rays.size());
}

Surface surface(SphereView spheres, const Ray& ray, const Hit& hit) {
  const Vec3 p = ray.at(hit.t);
  if (!hit.found() || hit.id >= spheres.count) return {p, {0.0f, 0.0f, 0.0f}, false};
  const Vec3 center{spheres.cx[hit.id], spheres.cy[hit.id], spheres.cz[hit.id]};
  const float radius = spheres.radius[hit.id];
  // The normal from the centre, not (p - centre) / radius: p is off the sphere by t's rounding,
  // and normalising keeps the normal unit length whatever that error. The point is then put
  // back on the sphere along it, so secondary rays start from the surface itself.
  // A hit at the very centre (radius below float's resolution) has no direction from it: face
  // the ray instead, so the normal is still unit length.
  // The offset is divided by its largest component before it is normalised: the squares of a
  // tiny one (a sphere of radius 1e-22) fall into float's denormals, whose few bits would make
  // the normal's length wrong by percents.
  const Vec3 from_center = p - center;
  const float largest =
      std::max({std::fabs(from_center.x), std::fabs(from_center.y), std::fabs(from_center.z)});
  const bool has_direction = isfinite(from_center) && largest > 0.0f;
  const Vec3 normal = has_direction ? normalize(from_center / largest) : -normalize(ray.dir);
  return {center + radius * normal, normal, dot(ray.dir, normal) < 0.0f};
}

}  // namespace sphray
