// Sphere storage: SphereView reads any structure-of-arrays; SphereSoA owns aligned, padded
// arrays whose views the kernel can read in whole SIMD batches (SphereViewd and SphereSoAd: the
// same in double).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "sphray/api.h"
#include "sphray/ray.hpp"
#include "sphray/vec3.hpp"

namespace sphray {

/// A non-owning structure-of-arrays view of spheres, float (SphereView) or double (SphereViewd):
/// sphere i has centre (cx[i], cy[i], cz[i]) and radius radius[i], and id i. Any alignment, any
/// count.
///
/// mask, when not null, gives each sphere a 32-bit mask: a ray sees sphere i only if
/// mask[i] & ray.mask != 0 (docs/queries.md, "Masks"). Null: every sphere has every bit, and the
/// queries take their unmasked path, at no cost.
///
/// padded_count is an optional promise: entries [count, padded_count) of the four arrays are
/// readable and hold spheres that are never hit (radius <= 0). The kernel then reads whole
/// batches up to padded_count instead of copying a partial last batch. Leave it 0 if unsure.
template <Scalar S>
struct BasicSphereView {
  const S* cx;
  const S* cy;
  const S* cz;
  const S* radius;
  std::size_t count;
  std::size_t padded_count = 0;
  const std::uint32_t* mask = nullptr;  // readable up to padded_count as well, if that is set
};

using SphereView = BasicSphereView<float>;
using SphereViewd = BasicSphereView<double>;

/// Owning structure-of-arrays sphere storage, float (SphereSoA) or double (SphereSoAd). Each
/// array starts on a kAlignment-byte boundary and is padded with never-hit spheres to a multiple
/// of kPadding, the widest SIMD batch, so the kernel never handles a partial batch on its views.
/// Ids are insertion indices.
template <Scalar S>
class SPHRAY_API BasicSphereSoA {
 public:
  static constexpr std::size_t kAlignment = 64;
  static constexpr std::size_t kPadding = 16;

  BasicSphereSoA() = default;
  BasicSphereSoA(const BasicSphereSoA& other);
  BasicSphereSoA& operator=(const BasicSphereSoA& other);
  BasicSphereSoA(BasicSphereSoA&&) noexcept = default;
  BasicSphereSoA& operator=(BasicSphereSoA&&) noexcept = default;
  ~BasicSphereSoA() = default;

  /// Appends a sphere and returns its id. Throws std::length_error past 2^32 - 1 spheres.
  /// When size() reaches capacity() the arrays are reallocated: every SphereView taken
  /// earlier then points at freed memory and must be taken again (reserve() first to add
  /// without reallocating). A SphereBVH keeps its own copy and is not affected.
  std::uint32_t add(BasicVec3<S> center, S radius, std::uint32_t mask = kAllBits);
  /// Replaces sphere id. Throws std::out_of_range if id >= size().
  void set(std::uint32_t id, BasicVec3<S> center, S radius);

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  std::size_t capacity() const { return capacity_; }
  void reserve(std::size_t n);
  void clear();

  BasicVec3<S> center(std::uint32_t id) const { return {x(id), y(id), z(id)}; }
  S radius(std::uint32_t id) const { return array(3)[id]; }
  /// The mask rays must share a bit with to see sphere id. The mask array is made on the first
  /// mask other than kAllBits; until then views carry no mask. Throws std::out_of_range if
  /// id >= size().
  void set_mask(std::uint32_t id, std::uint32_t mask);
  std::uint32_t mask(std::uint32_t id) const { return masks_.empty() ? kAllBits : masks_[id]; }

  /// A view of the current arrays. It stays valid until they are reallocated or freed: an
  /// add() at size() == capacity(), a reserve() beyond capacity(), an assignment to or from
  /// this object (a move), or its destruction. set() and clear() keep the arrays (the view's
  /// count is the size at the time it was taken).
  BasicSphereView<S> view() const;

 private:
  S x(std::size_t i) const { return array(0)[i]; }
  S y(std::size_t i) const { return array(1)[i]; }
  S z(std::size_t i) const { return array(2)[i]; }
  S* array(int k) const { return data_.get() + k * capacity_; }
  void reallocate(std::size_t capacity);

  struct AlignedDelete {
    void operator()(S* p) const;
  };
  // One allocation holds the four arrays back to back (cx, cy, cz, radius), each capacity_
  // long; capacity_ is a multiple of kPadding, so every array stays aligned.
  std::unique_ptr<S[], AlignedDelete> data_;
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
  // Empty, or capacity_ masks (the padding's kAllBits: its radius-0 spheres are never hit).
  std::vector<std::uint32_t> masks_;
};

using SphereSoA = BasicSphereSoA<float>;
using SphereSoAd = BasicSphereSoA<double>;
extern template class BasicSphereSoA<float>;
extern template class BasicSphereSoA<double>;

}  // namespace sphray
