// The public every-hit queries: each forwards to the kernel chosen at run time, the brute-force
// ones by the view's size as the closest-hit queries are (dispatch/query.cpp), the tree's to
// the kernel it was built for.
#include "sphray/all_hits.hpp"

#include <algorithm>
#include <stdexcept>
#include <type_traits>

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

// The batch forms, one body for both precisions: counts[i] = all(rays[i], its per_ray slots),
// all being one kernel's entry, looked up once per batch.
template <class RayS, class HitS, class All>
void each_ray(std::span<const RayS> rays, std::span<HitS> out, std::size_t per_ray,
              std::span<std::size_t> counts, All&& all) {
  check_batch(rays.size(), counts.size(), out.size(), per_ray);
  for (std::size_t i = 0; i < rays.size(); ++i)
    counts[i] = all(rays[i], out.data() + i * per_ray);
}

template <Scalar S>
void view_all(BasicSphereView<S> spheres, std::span<const BasicRay<S>> rays,
              std::span<BasicHit<S>> out, std::size_t per_ray, std::span<std::size_t> counts) {
  // The kernels the single-ray forms use: by the view's size in float, the process's in double.
  const detail::EntryTable& e =
      std::is_same_v<S, float> ? detail::entries_for_size(spheres.count) : detail::active_entries();
  const auto all = detail::in_precision<S>(e.intersect_all, e.intersect_all_d);
  each_ray(rays, out, per_ray, counts, [&](const BasicRay<S>& ray, BasicHit<S>* slots) {
    return all(spheres, ray, slots, nullptr, per_ray);
  });
}

template <Scalar S>
void tree_all_batch(const BasicSphereBVH<S>& bvh, std::span<const BasicRay<S>> rays,
                    std::span<BasicHit<S>> out, std::size_t per_ray,
                    std::span<std::size_t> counts) {
  using A = detail::BvhAccess;
  const auto& data = A::data(bvh);
  const detail::EntryTable& e = A::entries(bvh);
  const auto all = detail::in_precision<S>(e.bvh_intersect_all, e.bvh_intersect_all_d);
  each_ray(rays, out, per_ray, counts, [&](const BasicRay<S>& ray, BasicHit<S>* slots) {
    return all(data, ray, slots, nullptr, per_ray);
  });
}

template <Scalar S>
void tree_nearest_batch(const BasicSphereBVH<S>& bvh, std::span<const BasicRay<S>> rays,
                        std::span<BasicHit<S>> out, std::size_t per_ray,
                        std::span<std::size_t> counts) {
  each_ray(rays, out, per_ray, counts, [&](const BasicRay<S>& ray, BasicHit<S>* slots) {
    return tree_nearest(bvh, ray, std::span<BasicHit<S>>(slots, per_ray), {});
  });
}

// Brute force reads every sphere either way: the nearest are every crossing's first.
template <Scalar S>
void view_nearest_batch(BasicSphereView<S> spheres, std::span<const BasicRay<S>> rays,
                        std::span<BasicHit<S>> out, std::size_t per_ray,
                        std::span<std::size_t> counts) {
  view_all(spheres, rays, out, per_ray, counts);
  for (std::size_t& count : counts)
    count = std::min(count, per_ray);
}

}  // namespace

void count_hits(SphereView spheres, std::span<const Ray> rays, std::span<std::size_t> counts) {
  view_all<float>(spheres, rays, {}, 0, counts);
}
void count_hits(SphereViewd spheres, std::span<const Rayd> rays, std::span<std::size_t> counts) {
  view_all<double>(spheres, rays, {}, 0, counts);
}
void count_hits(const SphereBVH& bvh, std::span<const Ray> rays, std::span<std::size_t> counts) {
  tree_all_batch<float>(bvh, rays, {}, 0, counts);
}
void count_hits(const SphereBVHd& bvh, std::span<const Rayd> rays, std::span<std::size_t> counts) {
  tree_all_batch<double>(bvh, rays, {}, 0, counts);
}

void intersect_all(SphereView spheres, std::span<const Ray> rays, std::span<Hit> out,
                   std::size_t per_ray, std::span<std::size_t> counts) {
  view_all(spheres, rays, out, per_ray, counts);
}
void intersect_all(SphereViewd spheres, std::span<const Rayd> rays, std::span<Hitd> out,
                   std::size_t per_ray, std::span<std::size_t> counts) {
  view_all(spheres, rays, out, per_ray, counts);
}
void intersect_all(const SphereBVH& bvh, std::span<const Ray> rays, std::span<Hit> out,
                   std::size_t per_ray, std::span<std::size_t> counts) {
  tree_all_batch(bvh, rays, out, per_ray, counts);
}
void intersect_all(const SphereBVHd& bvh, std::span<const Rayd> rays, std::span<Hitd> out,
                   std::size_t per_ray, std::span<std::size_t> counts) {
  tree_all_batch(bvh, rays, out, per_ray, counts);
}

void intersect_nearest(SphereView spheres, std::span<const Ray> rays, std::span<Hit> out,
                       std::size_t per_ray, std::span<std::size_t> counts) {
  view_nearest_batch(spheres, rays, out, per_ray, counts);
}
void intersect_nearest(SphereViewd spheres, std::span<const Rayd> rays, std::span<Hitd> out,
                       std::size_t per_ray, std::span<std::size_t> counts) {
  view_nearest_batch(spheres, rays, out, per_ray, counts);
}
void intersect_nearest(const SphereBVH& bvh, std::span<const Ray> rays, std::span<Hit> out,
                       std::size_t per_ray, std::span<std::size_t> counts) {
  tree_nearest_batch(bvh, rays, out, per_ray, counts);
}
void intersect_nearest(const SphereBVHd& bvh, std::span<const Rayd> rays, std::span<Hitd> out,
                       std::size_t per_ray, std::span<std::size_t> counts) {
  tree_nearest_batch(bvh, rays, out, per_ray, counts);
}

}  // namespace sphray
