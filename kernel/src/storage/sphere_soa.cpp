#include "sphray/spheres.hpp"
#include "storage/huge_pages.hpp"

#include "sphray/ray.hpp"

#include <algorithm>
#include <cstring>
#include <new>
#include <stdexcept>

namespace sphray {
namespace {
// Ids are 32-bit and kNoHit is reserved.
constexpr std::size_t kMaxSpheres = kNoHit;
}  // namespace

void SphereSoA::AlignedDelete::operator()(float* p) const {
  ::operator delete[](p, std::align_val_t{kAlignment});
}

SphereSoA::SphereSoA(const SphereSoA& other) {
  *this = other;
}

SphereSoA& SphereSoA::operator=(const SphereSoA& other) {
  if (this == &other) return *this;
  clear();
  reallocate(other.capacity_);
  if (capacity_ != 0) std::memcpy(data_.get(), other.data_.get(), 4 * capacity_ * sizeof(float));
  size_ = other.size_;
  masks_ = other.masks_;
  return *this;
}

// The padding past size_ (up to a multiple of kPadding) always holds radius-0 spheres, which
// are never hit: the zero-initialised allocation and clear() keep it so.
void SphereSoA::reallocate(std::size_t capacity) {
  capacity = (capacity + kPadding - 1) / kPadding * kPadding;
  if (capacity == 0) {
    data_.reset();
    capacity_ = 0;
    masks_.clear();
    return;
  }
  std::unique_ptr<float[], AlignedDelete> data(static_cast<float*>(
      ::operator new[](4 * capacity * sizeof(float), std::align_val_t{kAlignment})));
  detail::prefer_huge_pages(data.get(), 4 * capacity * sizeof(float));
  std::fill_n(data.get(), 4 * capacity, 0.0f);
  for (int k = 0; k < 4; ++k)
    if (size_ != 0) std::memcpy(data.get() + k * capacity, array(k), size_ * sizeof(float));
  data_ = std::move(data);
  capacity_ = capacity;
  if (!masks_.empty()) masks_.resize(capacity_, kAllBits);
}

void SphereSoA::reserve(std::size_t n) {
  if (n > kMaxSpheres) throw std::length_error("sphray::SphereSoA: more than 2^32 - 1 spheres");
  if (n > capacity_) reallocate(n);
}

std::uint32_t SphereSoA::add(Vec3 center, float radius, std::uint32_t mask) {
  if (size_ == kMaxSpheres)
    throw std::length_error("sphray::SphereSoA: more than 2^32 - 1 spheres");
  if (size_ == capacity_) reserve(std::clamp<std::size_t>(2 * capacity_, kPadding, kMaxSpheres));
  const auto id = static_cast<std::uint32_t>(size_++);
  set(id, center, radius);
  if (mask != kAllBits || !masks_.empty()) set_mask(id, mask);
  return id;
}

void SphereSoA::set_mask(std::uint32_t id, std::uint32_t mask) {
  if (id >= size_) throw std::out_of_range("sphray::SphereSoA::set_mask: id out of range");
  if (masks_.empty()) {
    if (mask == kAllBits) return;
    masks_.assign(capacity_, kAllBits);
  }
  masks_[id] = mask;
}

void SphereSoA::set(std::uint32_t id, Vec3 center, float radius) {
  if (id >= size_) throw std::out_of_range("sphray::SphereSoA::set: id out of range");
  array(0)[id] = center.x;
  array(1)[id] = center.y;
  array(2)[id] = center.z;
  array(3)[id] = radius;
}

void SphereSoA::clear() {
  for (int k = 0; k < 4; ++k)
    if (size_ != 0) std::fill_n(array(k), size_, 0.0f);
  size_ = 0;
  masks_.clear();
}

SphereView SphereSoA::view() const {
  if (capacity_ == 0) return {nullptr, nullptr, nullptr, nullptr, 0, 0};
  return {array(0),
          array(1),
          array(2),
          array(3),
          size_,
          (size_ + kPadding - 1) / kPadding * kPadding,
          masks_.empty() ? nullptr : masks_.data()};
}

}  // namespace sphray
