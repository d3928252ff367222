// SphereBVH: owns the built arrays and forwards queries to the kernel it was laid out for.
#include "sphray/bvh.hpp"

#include <array>
#include <mutex>
#include <stdexcept>
#include <string>

#include "bvh/build.hpp"

namespace sphray {

struct SphereBVH::Storage {
  detail::BvhArrays arrays;
};

namespace {

// The number of Isa enumerators: a value cast from anything else names no instruction set.
constexpr std::size_t kIsaCount = 5;

const Kernel& kernel_for(Isa isa) {
  const auto index = static_cast<std::size_t>(isa);
  if (index >= kIsaCount) {
    throw std::invalid_argument("sphray::SphereBVH: " + std::to_string(index) +
                                " is not an instruction set");
  }
  const Kernel* k = find_kernel(isa);
  if (k == nullptr)
    throw std::invalid_argument("sphray::SphereBVH: instruction set " + std::string(isa_name(isa)) +
                                " cannot run here");
  return *k;
}

// The empty tree of each instruction set, built once and never freed: what a moved-from
// SphereBVH points at, so that its queries miss and size() is 0 without an allocation in the
// noexcept move. Built (and so allocated) by every constructor before any move can need it.
const detail::BvhData& empty_tree(const Kernel& kernel) {
  static std::mutex mutex;
  static std::array<std::unique_ptr<detail::BvhArrays>, kIsaCount> trees;
  static std::array<detail::BvhData, kIsaCount> data;
  const std::lock_guard lock(mutex);
  const auto index = static_cast<std::size_t>(kernel.isa);
  if (!trees[index]) {
    trees[index] = std::make_unique<detail::BvhArrays>(detail::build_bvh(
        SphereView{nullptr, nullptr, nullptr, nullptr, 0, 0}, kernel.bvh_width, {}));
    data[index] = trees[index]->data();
  }
  return data[index];
}

}  // namespace

SphereBVH::SphereBVH() : SphereBVH(SphereView{nullptr, nullptr, nullptr, nullptr, 0, 0}) {}

SphereBVH::SphereBVH(SphereView spheres, BvhBuildOptions options)
    : SphereBVH(spheres, active_isa(), options) {}

SphereBVH::SphereBVH(SphereView spheres, Isa isa, BvhBuildOptions options)
    : kernel_(&kernel_for(isa)) {
  empty_tree(*kernel_);  // a later move leaves this object (or another) pointing at it
  storage_ =
      std::make_unique<Storage>(Storage{detail::build_bvh(spheres, kernel_->bvh_width, options)});
  data_ = storage_->arrays.data();
}

SphereBVH::SphereBVH(SphereBVH&& other) noexcept
    : storage_(std::move(other.storage_)), data_(other.data_), kernel_(other.kernel_) {
  other.become_empty();
}

SphereBVH& SphereBVH::operator=(SphereBVH&& other) noexcept {
  if (this != &other) {
    storage_ = std::move(other.storage_);
    data_ = other.data_;
    kernel_ = other.kernel_;
    other.become_empty();
  }
  return *this;
}

SphereBVH::~SphereBVH() = default;

void SphereBVH::become_empty() noexcept {
  storage_.reset();
  data_ = empty_tree(*kernel_);  // built when this tree was: no allocation here
}

void SphereBVH::refit(SphereView spheres) {
  if (!storage_) {  // moved from: refit the empty tree it stands for (a count of 0 only)
    storage_ = std::make_unique<Storage>(Storage{detail::build_bvh(
        SphereView{nullptr, nullptr, nullptr, nullptr, 0, 0}, kernel_->bvh_width, {})});
  }
  detail::refit_bvh(storage_->arrays, spheres);
  data_ = storage_->arrays.data();  // the leaf overlap changed
}

std::size_t SphereBVH::size() const {
  return data_.count;
}

Isa SphereBVH::isa() const {
  return kernel_->isa;
}

std::size_t SphereBVH::memory_bytes() const {
  return storage_ ? storage_->arrays.memory_bytes() : 0;
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
