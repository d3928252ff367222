// The output of the every-hit queries (float or double): the nearest crossings found so far, kept
// sorted in the caller's span, and how many there were in all. Each instruction set's unit compiles
// its own copy (simd/isa_namespace.hpp); the scalar reference shares the baseline one.
#pragma once

#include <cstddef>
#include <cstdint>

#include "simd/isa_namespace.hpp"
#include "sphray/ray.hpp"

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

template <class S>
class BasicHitList {
 public:
  using HitS = BasicHit<S>;

  /// exits may be null: the caller does not want them. Then two crossings that differ only in
  /// being an entry or an exit (a tangent ray's two equal roots) are the same Hit, and their
  /// order needs no flag.
  BasicHitList(HitS* hits, bool* exits, std::size_t capacity)
      : hits_(hits), exits_(exits), capacity_(capacity) {}

  /// A crossing of sphere id at t, in the contract's order: by t, then id, then entry before
  /// exit. Insertion into a sorted array: the list is short (the caller's capacity), and a
  /// crossing behind the last kept one, the common case once it is full, costs one comparison.
  void add(S t, std::uint32_t id, bool exit) {
    ++total_;
    if (capacity_ == 0) return;
    if (size_ == capacity_ && !before(t, id, exit, capacity_ - 1)) return;
    std::size_t i = size_ < capacity_ ? size_++ : capacity_ - 1;
    for (; i > 0 && before(t, id, exit, i - 1); --i) {
      hits_[i] = hits_[i - 1];
      if (exits_ != nullptr) exits_[i] = exits_[i - 1];
    }
    hits_[i] = HitS{t, id};
    if (exits_ != nullptr) exits_[i] = exit;
  }

  /// Counts crossings that need no place in the list (it has no room at all).
  void count(std::size_t n) { total_ += n; }
  bool counts_only() const { return capacity_ == 0; }
  /// Whether a crossing must be placed at all: once the list is full, only one at or before
  /// the last kept t can be (ties are then ordered by add()).
  bool full() const { return size_ == capacity_; }
  S last_t() const { return hits_[capacity_ - 1].t; }

  std::size_t size() const { return size_; }
  std::size_t total() const { return total_; }

 private:
  // Whether (t, id, exit) goes before the crossing kept at index i.
  bool before(S t, std::uint32_t id, bool exit, std::size_t i) const {
    if (t != hits_[i].t) return t < hits_[i].t;
    if (id != hits_[i].id) return id < hits_[i].id;
    return exits_ != nullptr && !exit && exits_[i];
  }

  HitS* hits_;
  bool* exits_;
  std::size_t capacity_;
  std::size_t size_ = 0;
  std::size_t total_ = 0;
};

using HitList = BasicHitList<float>;

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
