// The public every-hit queries: each forwards to the kernel chosen at run time, the brute-force
// ones by the view's size as the closest-hit queries are (dispatch/query.cpp), the tree's to
// the kernel it was built for.
#include "sphray/all_hits.hpp"

#include <algorithm>
#include <stdexcept>

#include "bvh/bvh_data.hpp"
#include "dispatch/entry_table.hpp"

namespace sphray {
namespace {

template <class HitS>
bool* exit_flags(std::span<HitS> out, std::span<bool> exits) {
  if (exits.empty()) return nullptr;
  if (exits.size() != out.size())
    throw std::length_error("sphray::intersect_all: hits and exits differ in size");
  return exits.data();
}

template <Scalar S>
std::size_t tree_all(const BasicSphereBVH<S>& bvh, const BasicRay<S>& ray,
                     std::span<BasicHit<S>> out, std::span<bool> exits) {
  bool* flags = exit_flags(out, exits);
  using A = detail::BvhAccess;
  const detail::EntryTable& e = A::entries(bvh);
  return detail::in_precision<S>(e.bvh_intersect_all, e.bvh_intersect_all_d)(
      A::data(bvh), ray, out.data(), flags, out.size());
}

template <Scalar S>
std::size_t tree_nearest(const BasicSphereBVH<S>& bvh, const BasicRay<S>& ray,
                         std::span<BasicHit<S>> out, std::span<bool> exits) {
  bool* flags = exit_flags(out, exits);
  if (out.empty()) return 0;
  using A = detail::BvhAccess;
  const detail::EntryTable& e = A::entries(bvh);
  return detail::in_precision<S>(e.bvh_intersect_nearest, e.bvh_intersect_nearest_d)(
      A::data(bvh), ray, out.data(), flags, out.size());
}

}  // namespace

std::size_t intersect_all(SphereView spheres, const Ray& ray, std::span<Hit> out,
                          std::span<bool> exits) {
  bool* flags = exit_flags(out, exits);
  return detail::entries_for_size(spheres.count)
      .intersect_all(spheres, ray, out.data(), flags, out.size());
}

std::size_t intersect_all(SphereViewd spheres, const Rayd& ray, std::span<Hitd> out,
                          std::span<bool> exits) {
  bool* flags = exit_flags(out, exits);
  return detail::active_entries().intersect_all_d(spheres, ray, out.data(), flags, out.size());
}

std::size_t count_hits(SphereViewd spheres, const Rayd& ray) {
  return intersect_all(spheres, ray, {}, {});
}

std::size_t intersect_all(SphereView spheres, const Ray& ray, std::span<Hit> out) {
  return intersect_all(spheres, ray, out, {});
}

std::size_t count_hits(SphereView spheres, const Ray& ray) {
  return intersect_all(spheres, ray, {}, {});
}

std::size_t intersect_all(const SphereBVH& bvh, const Ray& ray, std::span<Hit> out,
                          std::span<bool> exits) {
  return tree_all(bvh, ray, out, exits);
}

std::size_t intersect_all(const SphereBVHd& bvh, const Rayd& ray, std::span<Hitd> out,
                          std::span<bool> exits) {
  return tree_all(bvh, ray, out, exits);
}

std::size_t count_hits(const SphereBVHd& bvh, const Rayd& ray) {
  return tree_all(bvh, ray, {}, {});
}

std::size_t intersect_all(const SphereBVH& bvh, const Ray& ray, std::span<Hit> out) {
  return intersect_all(bvh, ray, out, {});
}

std::size_t count_hits(const SphereBVH& bvh, const Ray& ray) {
  return intersect_all(bvh, ray, {}, {});
}

std::size_t intersect_nearest(SphereView spheres, const Ray& ray, std::span<Hit> out,
                              std::span<bool> exits) {
  // Brute force reads every sphere either way: the nearest are every crossing's first.
  return std::min(intersect_all(spheres, ray, out, exits), out.size());
}

std::size_t intersect_nearest(SphereView spheres, const Ray& ray, std::span<Hit> out) {
  return intersect_nearest(spheres, ray, out, {});
}

std::size_t intersect_nearest(const SphereBVH& bvh, const Ray& ray, std::span<Hit> out,
                              std::span<bool> exits) {
  return tree_nearest(bvh, ray, out, exits);
}

std::size_t intersect_nearest(const SphereBVHd& bvh, const Rayd& ray, std::span<Hitd> out,
                              std::span<bool> exits) {
  return tree_nearest(bvh, ray, out, exits);
}

std::size_t intersect_nearest(SphereViewd spheres, const Rayd& ray, std::span<Hitd> out,
                              std::span<bool> exits) {
  return std::min(intersect_all(spheres, ray, out, exits), out.size());
}

std::size_t intersect_nearest(const SphereBVH& bvh, const Ray& ray, std::span<Hit> out) {
  return intersect_nearest(bvh, ray, out, {});
}

namespace {

// out must hold per_ray hits for each ray (written without overflowing rays * per_ray).
void check_batch(std::size_t rays, std::size_t counts, std::size_t out, std::size_t per_ray) {
  const bool fits = per_ray == 0 ? out == 0 : out % per_ray == 0 && out / per_ray == rays;
  if (counts != rays || !fits)
    throw std::length_error(
        "sphray::intersect_all: expected one count per ray and per_ray hits for each");
}

}  // namespace

void count_hits(SphereView spheres, std::span<const Ray> rays, std::span<std::size_t> counts) {
  intersect_all(spheres, rays, {}, 0, counts);
}

void count_hits(const SphereBVH& bvh, std::span<const Ray> rays, std::span<std::size_t> counts) {
  intersect_all(bvh, rays, {}, 0, counts);
}

void intersect_all(SphereView spheres, std::span<const Ray> rays, std::span<Hit> out,
                   std::size_t per_ray, std::span<std::size_t> counts) {
  check_batch(rays.size(), counts.size(), out.size(), per_ray);
  const detail::EntryTable& entries = detail::entries_for_size(spheres.count);
  for (std::size_t i = 0; i < rays.size(); ++i)
    counts[i] = entries.intersect_all(spheres, rays[i], out.data() + i * per_ray, nullptr, per_ray);
}

void intersect_all(const SphereBVH& bvh, std::span<const Ray> rays, std::span<Hit> out,
                   std::size_t per_ray, std::span<std::size_t> counts) {
  check_batch(rays.size(), counts.size(), out.size(), per_ray);
  using A = detail::BvhAccess;
  const detail::BvhData& data = A::data(bvh);
  const detail::EntryTable& entries = A::entries(bvh);
  for (std::size_t i = 0; i < rays.size(); ++i)
    counts[i] =
        entries.bvh_intersect_all(data, rays[i], out.data() + i * per_ray, nullptr, per_ray);
}

void intersect_nearest(const SphereBVH& bvh, std::span<const Ray> rays, std::span<Hit> out,
                       std::size_t per_ray, std::span<std::size_t> counts) {
  check_batch(rays.size(), counts.size(), out.size(), per_ray);
  for (std::size_t i = 0; i < rays.size(); ++i)
    counts[i] = intersect_nearest(bvh, rays[i], out.subspan(i * per_ray, per_ray));
}

void intersect_nearest(SphereView spheres, std::span<const Ray> rays, std::span<Hit> out,
                       std::size_t per_ray, std::span<std::size_t> counts) {
  intersect_all(spheres, rays, out, per_ray, counts);
  for (std::size_t& count : counts)
    count = std::min(count, per_ray);
}

}  // namespace sphray
