// The public brute-force queries: each forwards to the kernel chosen at run time.
#include "sphray/query.hpp"

#include <stdexcept>

#include "dispatch/entry_table.hpp"
#include "dispatch/query_plan.hpp"
#include "sphray/isa.hpp"
#include "storage/ray_columns.hpp"

namespace sphray {

// Views below kScalarBelow spheres go straight to the scalar loop, as entries_for_size() would
// send them: a ray against one sphere costs so little that looking the kernel up is a sizeable
// share of it (docs/history.md, "Small scenes against Embree: the targets still missed").
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

namespace {
// The kernel of a stream on a view, looked up once for the whole stream: with the rays across
// the lanes (QueryPlan::rays_across) the active instruction set, whose lanes hold the most
// rays; otherwise the one for the view's size, as for a single ray.
const detail::EntryTable& stream_entries(std::size_t sphere_count) {
  if (detail::SPHRAY_ISA_NAMESPACE::QueryPlan::rays_across(sphere_count))
    return detail::active_entries();
  return detail::entries_for_size(sphere_count);
}
}  // namespace

void intersect(SphereView spheres, std::span<const Ray> rays, std::span<Hit> hits) {
  if (rays.size() != hits.size())
    throw std::length_error("sphray::intersect: rays and hits differ in size");
  stream_entries(spheres.count).intersect_stream(spheres, rays.data(), hits.data(), rays.size());
}

void intersect(SphereView spheres, const RayArrays& rays, const HitArrays& hits) {
  detail::check_arrays(rays, hits);
  stream_entries(spheres.count).intersect_arrays(spheres, rays, hits);
}

void occluded(SphereView spheres, std::span<const Ray> rays, std::span<bool> blocked) {
  if (rays.size() != blocked.size())
    throw std::length_error("sphray::occluded: rays and blocked differ in size");
  stream_entries(spheres.count).occluded_stream(spheres, rays.data(), blocked.data(), rays.size());
}

// Double: the active instruction set whatever the view's size (entries_for_size() measures
// float's batches), and the scalar loop for the views it would send there.
Hitd intersect(SphereViewd spheres, const Rayd& ray) {
  if (detail::SPHRAY_ISA_NAMESPACE::QueryPlan::scalar(spheres.count))
    return scalar::intersect(spheres, ray);
  return detail::active_entries().intersect_d(spheres, ray);
}

bool occluded(SphereViewd spheres, const Rayd& ray) {
  if (detail::SPHRAY_ISA_NAMESPACE::QueryPlan::scalar(spheres.count))
    return scalar::occluded(spheres, ray);
  return detail::active_entries().occluded_d(spheres, ray);
}

void intersect(SphereViewd spheres, std::span<const Rayd> rays, std::span<Hitd> hits) {
  if (rays.size() != hits.size())
    throw std::length_error("sphray::intersect: rays and hits differ in size");
  detail::active_entries().intersect_stream_d(spheres, rays.data(), hits.data(), rays.size());
}

void intersect(SphereViewd spheres, const RayArraysd& rays, const HitArraysd& hits) {
  detail::check_arrays(rays, hits);
  detail::intersect_in_chunks(rays, hits, [&](std::span<const Rayd> in, std::span<Hitd> out) {
    intersect(spheres, in, out);
  });
}

void occluded(SphereViewd spheres, std::span<const Rayd> rays, std::span<bool> blocked) {
  if (rays.size() != blocked.size())
    throw std::length_error("sphray::occluded: rays and blocked differ in size");
  detail::active_entries().occluded_stream_d(spheres, rays.data(), blocked.data(), rays.size());
}

}  // namespace sphray
