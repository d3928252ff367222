// The public brute-force queries: each forwards to the kernel chosen at run time.
#include "sphray/query.hpp"

#include <stdexcept>

#include "dispatch/entry_table.hpp"
#include "dispatch/query_plan.hpp"
#include "sphray/isa.hpp"
#include "storage/ray_columns.hpp"

namespace sphray {

// Views below kScalarBelow spheres go straight to the scalar loop, as entries_for_size() would
// send them: a ray against one sphere takes a few nanoseconds, and looking the kernel up measured
// a fifth of that.
Hit intersect(SphereView spheres, const Ray& ray) {
  if (detail::SPHRAY_ISA_NAMESPACE::QueryPlan::scalar(spheres.count))
    return scalar::intersect(spheres, ray);
  return detail::entries_for_size(spheres.count).intersect(spheres, ray);
}

bool occluded(SphereView spheres, const Ray& ray) {
  if (detail::SPHRAY_ISA_NAMESPACE::QueryPlan::scalar(spheres.count))
    return scalar::occluded(spheres, ray);
  return detail::entries_for_size(spheres.count).occluded(spheres, ray);
}

void intersect(SphereView spheres, std::span<const Ray> rays, std::span<Hit> hits) {
  if (rays.size() != hits.size())
    throw std::length_error("sphray::intersect: rays and hits differ in size");
  detail::entries_for_size(spheres.count)
      .intersect_stream(spheres, rays.data(), hits.data(), rays.size());
}

void intersect(SphereView spheres, const RayArrays& rays, const HitArrays& hits) {
  detail::check_arrays(rays, hits);
  detail::entries_for_size(spheres.count).intersect_arrays(spheres, rays, hits);
}

// The kernel looked up once for the whole stream; a view has no packets, every ray goes alone.
void occluded(SphereView spheres, std::span<const Ray> rays, std::span<bool> blocked) {
  if (rays.size() != blocked.size())
    throw std::length_error("sphray::occluded: rays and blocked differ in size");
  if (detail::SPHRAY_ISA_NAMESPACE::QueryPlan::scalar(spheres.count)) {
    for (std::size_t i = 0; i < rays.size(); ++i)
      blocked[i] = scalar::occluded(spheres, rays[i]);
    return;
  }
  const detail::EntryTable& entries = detail::entries_for_size(spheres.count);
  for (std::size_t i = 0; i < rays.size(); ++i)
    blocked[i] = entries.occluded(spheres, rays[i]);
}

}  // namespace sphray
