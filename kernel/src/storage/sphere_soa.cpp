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

template <Scalar S>
void BasicSphereSoA<S>::AlignedDelete::operator()(S* p) const {
  ::operator delete[](p, std::align_val_t{kAlignment});
}

template <Scalar S>
BasicSphereSoA<S>::BasicSphereSoA(const BasicSphereSoA& other) {
  *this = other;
}

template <Scalar S>
BasicSphereSoA<S>& BasicSphereSoA<S>::operator=(const BasicSphereSoA& other) {
  if (this == &other) return *this;
  clear();
  reallocate(other.capacity_);
  if (capacity_ != 0) std::memcpy(data_.get(), other.data_.get(), 4 * capacity_ * sizeof(S));
  size_ = other.size_;
  masks_ = other.masks_;
  return *this;
}

// The padding past size_ (up to a multiple of kPadding) always holds radius-0 spheres, which
// are never hit: the zero-initialised allocation and clear() keep it so.
template <Scalar S>
void BasicSphereSoA<S>::reallocate(std::size_t capacity) {
  capacity = (capacity + kPadding - 1) / kPadding * kPadding;
  if (capacity == 0) {
    data_.reset();
    capacity_ = 0;
    masks_.clear();
    return;
  }
  std::unique_ptr<S[], AlignedDelete> data(
      static_cast<S*>(::operator new[](4 * capacity * sizeof(S), std::align_val_t{kAlignment})));
  detail::prefer_huge_pages(data.get(), 4 * capacity * sizeof(S));
  std::fill_n(data.get(), 4 * capacity, S{0});
  for (int k = 0; k < 4; ++k)
    if (size_ != 0) std::memcpy(data.get() + k * capacity, array(k), size_ * sizeof(S));
  data_ = std::move(data);
  capacity_ = capacity;
  if (!masks_.empty()) masks_.resize(capacity_, kAllBits);
}

template <Scalar S>
void BasicSphereSoA<S>::reserve(std::size_t n) {
  if (n > kMaxSpheres) throw std::length_error("sphray::SphereSoA: more than 2^32 - 1 spheres");
  if (n > capacity_) reallocate(n);
}

template <Scalar S>
std::uint32_t BasicSphereSoA<S>::add(BasicVec3<S> center, S radius, std::uint32_t mask) {
  if (size_ == kMaxSpheres)
    throw std::length_error("sphray::SphereSoA: more than 2^32 - 1 spheres");
  if (size_ == capacity_) reserve(std::clamp<std::size_t>(2 * capacity_, kPadding, kMaxSpheres));
  const auto id = static_cast<std::uint32_t>(size_++);
  set(id, center, radius);
  if (mask != kAllBits || !masks_.empty()) set_mask(id, mask);
  return id;
}

template <Scalar S>
void BasicSphereSoA<S>::set_mask(std::uint32_t id, std::uint32_t mask) {
  if (id >= size_) throw std::out_of_range("sphray::SphereSoA::set_mask: id out of range");
  if (masks_.empty()) {
    if (mask == kAllBits) return;
    masks_.assign(capacity_, kAllBits);
  }
  masks_[id] = mask;
}

template <Scalar S>
void BasicSphereSoA<S>::set(std::uint32_t id, BasicVec3<S> center, S radius) {
  if (id >= size_) throw std::out_of_range("sphray::SphereSoA::set: id out of range");
  array(0)[id] = center.x;
  array(1)[id] = center.y;
  array(2)[id] = center.z;
  array(3)[id] = radius;
}

template <Scalar S>
void BasicSphereSoA<S>::clear() {
  for (int k = 0; k < 4; ++k)
    if (size_ != 0) std::fill_n(array(k), size_, S{0});
  size_ = 0;
  masks_.clear();
}

template <Scalar S>
BasicSphereView<S> BasicSphereSoA<S>::view() const {
  if (capacity_ == 0) return {nullptr, nullptr, nullptr, nullptr, 0, 0};
  return {array(0),
          array(1),
          array(2),
          array(3),
          size_,
          (size_ + kPadding - 1) / kPadding * kPadding,
          masks_.empty() ? nullptr : masks_.data()};
}

template class BasicSphereSoA<float>;
template class BasicSphereSoA<double>;

}  // namespace sphray
