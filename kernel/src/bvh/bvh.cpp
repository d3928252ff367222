// SphereBVH: owns the built arrays and forwards queries to the kernel it was laid out for.
#include "sphray/bvh.hpp"

#include <stdexcept>

#include "bvh/build.hpp"

namespace sphray {

struct SphereBVH::Storage {
  detail::BvhArrays arrays;
};

namespace {
const Kernel& kernel_for(Isa isa) {
  const Kernel* k = find_kernel(isa);
  if (k == nullptr)
    throw std::invalid_argument("sphray::SphereBVH: instruction set " + std::string(isa_name(isa)) +
                                " cannot run here");
  return *k;
}
}  // namespace

SphereBVH::SphereBVH() : SphereBVH(SphereView{nullptr, nullptr, nullptr, nullptr, 0, 0}) {}

SphereBVH::SphereBVH(SphereView spheres, BvhBuildOptions options)
    : SphereBVH(spheres, active_isa(), options) {}

SphereBVH::SphereBVH(SphereView spheres, Isa isa, BvhBuildOptions options)
    : kernel_(&kernel_for(isa)) {
  storage_ =
      std::make_unique<Storage>(Storage{detail::build_bvh(spheres, kernel_->bvh_width, options)});
  data_ = storage_->arrays.data();
}

SphereBVH::SphereBVH(SphereBVH&&) noexcept = default;
SphereBVH& SphereBVH::operator=(SphereBVH&&) noexcept = default;
SphereBVH::~SphereBVH() = default;

void SphereBVH::refit(SphereView spheres) {
  detail::refit_bvh(storage_->arrays, spheres);
  data_ = storage_->arrays.data();  // the leaf overlap changed
}

std::size_t SphereBVH::size() const {
  return storage_->arrays.source_count;
}

Isa SphereBVH::isa() const {
  return kernel_->isa;
}

std::size_t SphereBVH::memory_bytes() const {
  return storage_->arrays.memory_bytes();
}

Hit intersect(const SphereBVH& bvh, const Ray& ray) {
  return bvh.kernel().bvh_intersect(bvh.data(), ray);
}

bool occluded(const SphereBVH& bvh, const Ray& ray) {
  return bvh.kernel().bvh_occluded(bvh.data(), ray);
}

void intersect(const SphereBVH& bvh, std::span<const Ray> rays, std::span<Hit> hits) {
  if (rays.size() != hits.size())
    throw std::length_error("sphray::intersect: rays and hits differ in size");
  bvh.kernel().bvh_intersect_stream(bvh.data(), rays.data(), hits.data(), rays.size());
}

}  // namespace sphray
