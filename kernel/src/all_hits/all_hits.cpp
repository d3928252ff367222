// The public every-hit queries: each forwards to the kernel chosen at run time, the brute-force
// ones by the view's size as the closest-hit queries are (dispatch/query.cpp), the tree's to
// the kernel it was built for.
#include "sphray/all_hits.hpp"

#include <stdexcept>

#include "bvh/bvh_data.hpp"
#include "dispatch/entry_table.hpp"

namespace sphray {
namespace {

bool* exit_flags(std::span<Hit> out, std::span<bool> exits) {
  if (exits.empty()) return nullptr;
  if (exits.size() != out.size())
    throw std::length_error("sphray::intersect_all: hits and exits differ in size");
  return exits.data();
}

}  // namespace

std::size_t intersect_all(SphereView spheres, const Ray& ray, std::span<Hit> out,
                          std::span<bool> exits) {
  bool* flags = exit_flags(out, exits);
  return detail::entries_for_size(spheres.count)
      .intersect_all(spheres, ray, out.data(), flags, out.size());
}

std::size_t intersect_all(SphereView spheres, const Ray& ray, std::span<Hit> out) {
  return intersect_all(spheres, ray, out, {});
}

std::size_t count_hits(SphereView spheres, const Ray& ray) {
  return intersect_all(spheres, ray, {}, {});
}

std::size_t intersect_all(const SphereBVH& bvh, const Ray& ray, std::span<Hit> out,
                          std::span<bool> exits) {
  bool* flags = exit_flags(out, exits);
  using A = detail::BvhAccess;
  return A::entries(bvh).bvh_intersect_all(A::data(bvh), ray, out.data(), flags, out.size());
}

std::size_t intersect_all(const SphereBVH& bvh, const Ray& ray, std::span<Hit> out) {
  return intersect_all(bvh, ray, out, {});
}

std::size_t count_hits(const SphereBVH& bvh, const Ray& ray) {
  return intersect_all(bvh, ray, {}, {});
}

}  // namespace sphray
