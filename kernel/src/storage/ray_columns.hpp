// RayArrays and HitArrays as the stream code reads a `const Ray*` and writes a `Hit*`: rays[i]
// is a Ray (made from the arrays' entries i), rays + k the arrays from ray k on, hits[i] = hit
// stores a Hit's two fields. The stream code is written once over either (bvh/stream.hpp), so
// a ray given as arrays takes exactly the path, and gets exactly the hit, it would as a Ray.
// Per-ISA code (simd/isa_namespace.hpp): RayArrays::at, one public inline symbol for every
// unit, is not called here.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <span>
#include <stdexcept>

#include "simd/force_inline.hpp"
#include "simd/isa_namespace.hpp"
#include "sphray/ray.hpp"
#include "sphray/ray_arrays.hpp"

namespace sphray::detail {

/// The public stream calls' checks of their arrays (sphray/query.hpp).
template <Scalar S>
void check_arrays(const BasicRayArrays<S>& rays, const BasicHitArrays<S>& hits) {
  if (hits.count != rays.count)
    throw std::length_error("sphray::intersect: rays and hits differ in count");
  if (rays.count == 0) return;
  const bool ray_null = rays.ox == nullptr || rays.oy == nullptr || rays.oz == nullptr ||
                        rays.dx == nullptr || rays.dy == nullptr || rays.dz == nullptr;
  if (ray_null)
    throw std::invalid_argument("sphray::intersect: a ray origin or direction array is null");
  if (hits.t == nullptr || hits.id == nullptr)
    throw std::invalid_argument("sphray::intersect: a hit array is null");
}

/// hits from rays through stream(rays, hits), the span stream of Rayd and Hitd, a stack chunk
/// at a time: double's streams take one ray at a time (no packets, no walks in turns), so
/// arrays in double gain nothing from being read in place, and a chunk keeps the hits the span
/// stream's, bit for bit, with no second stream to keep in step. Not for per-ISA code.
template <class Stream>
void intersect_in_chunks(const RayArraysd& rays, const HitArraysd& hits, Stream stream) {
  constexpr std::size_t kChunk = 256;
  std::array<Rayd, kChunk> in;
  std::array<Hitd, kChunk> out;
  for (std::size_t start = 0; start < rays.count; start += kChunk) {
    const std::size_t n = std::min(kChunk, rays.count - start);
    for (std::size_t i = 0; i < n; ++i)
      in[i] = rays.at(start + i);
    stream(std::span<const Rayd>(in.data(), n), std::span<Hitd>(out.data(), n));
    for (std::size_t i = 0; i < n; ++i)
      hits.set(start + i, out[i]);
  }
}

}  // namespace sphray::detail

namespace sphray::detail::SPHRAY_ISA_NAMESPACE {

struct RayColumns {
  RayArrays arrays;

  SPHRAY_FORCE_INLINE Ray operator[](std::size_t i) const {
    const RayArrays& a = arrays;
    return {{a.ox[i], a.oy[i], a.oz[i]},
            {a.dx[i], a.dy[i], a.dz[i]},
            a.tmin != nullptr ? a.tmin[i] : 0.0f,
            a.tmax != nullptr ? a.tmax[i] : INFINITY,
            a.mask != nullptr ? a.mask[i] : kAllBits};
  }
  SPHRAY_FORCE_INLINE RayColumns operator+(std::size_t k) const {
    RayArrays a = arrays;
    a.ox += k, a.oy += k, a.oz += k, a.dx += k, a.dy += k, a.dz += k;
    if (a.tmin != nullptr) a.tmin += k;
    if (a.tmax != nullptr) a.tmax += k;
    if (a.mask != nullptr) a.mask += k;
    a.count -= k;
    return {a};
  }
};

struct HitColumns {
  HitArrays arrays;

  /// Where hit i goes: assigning a Hit stores it.
  struct Slot {
    float* t;
    std::uint32_t* id;
    SPHRAY_FORCE_INLINE const Slot& operator=(const Hit& hit) const {
      *t = hit.t;
      *id = hit.id;
      return *this;
    }
  };
  SPHRAY_FORCE_INLINE Slot operator[](std::size_t i) const { return {arrays.t + i, arrays.id + i}; }
  SPHRAY_FORCE_INLINE HitColumns operator+(std::size_t k) const {
    return {{arrays.t + k, arrays.id + k, arrays.count - k}};
  }
};

}  // namespace sphray::detail::SPHRAY_ISA_NAMESPACE
