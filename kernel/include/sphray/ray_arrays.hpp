// Rays and hits as one array per quantity: the layout a wavefront tracer keeps its paths in
// (Embree's stream calls take the same as RTCRayNp). The stream calls that take them
// (query.hpp, bvh.hpp) return what the Ray/Hit stream calls return, bit for bit, and spare the
// caller moving each ray into a Ray and each Hit out again.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sphray/ray.hpp"

namespace sphray {

/// count rays, ray i being {origin (ox[i], oy[i], oz[i]), dir (dx[i], dy[i], dz[i]), tmin[i],
/// tmax[i], mask[i]}. tmin, tmax and mask may be null: every ray then takes Ray's default
/// (0, infinity, every bit). The arrays are read only during the call; they need no alignment.
/// In float (RayArrays) or double (RayArraysd), as every type here.
template <Scalar S>
struct BasicRayArrays {
  const S* ox = nullptr;
  const S* oy = nullptr;
  const S* oz = nullptr;
  const S* dx = nullptr;
  const S* dy = nullptr;
  const S* dz = nullptr;
  const S* tmin = nullptr;
  const S* tmax = nullptr;
  const std::uint32_t* mask = nullptr;
  std::size_t count = 0;

  /// Ray i as a Ray.
  constexpr BasicRay<S> at(std::size_t i) const {
    return {{ox[i], oy[i], oz[i]},
            {dx[i], dy[i], dz[i]},
            tmin != nullptr ? tmin[i] : S(0),
            tmax != nullptr ? tmax[i] : S(INFINITY),
            mask != nullptr ? mask[i] : kAllBits};
  }
};

/// count hits: hit i is {t[i], id[i]}, as Hit (id kNoHit and t the ray's tmax for a miss).
template <Scalar S>
struct BasicHitArrays {
  S* t = nullptr;
  std::uint32_t* id = nullptr;
  std::size_t count = 0;

  constexpr BasicHit<S> at(std::size_t i) const { return {t[i], id[i]}; }
  constexpr void set(std::size_t i, const BasicHit<S>& hit) const {
    t[i] = hit.t;
    id[i] = hit.id;
  }
};

/// count surfaces, surface i being {point (px[i], py[i], pz[i]), normal (nx[i], ny[i], nz[i]),
/// front_face[i], error (ex[i], ey[i], ez[i])}: what surfaces() writes (query.hpp) and
/// offset_origins() reads. Every array holds count values.
template <Scalar S>
struct BasicSurfaceArrays {
  S* px = nullptr;
  S* py = nullptr;
  S* pz = nullptr;
  S* nx = nullptr;
  S* ny = nullptr;
  S* nz = nullptr;
  bool* front_face = nullptr;
  S* ex = nullptr;
  S* ey = nullptr;
  S* ez = nullptr;
  std::size_t count = 0;

  constexpr BasicSurface<S> at(std::size_t i) const {
    return {{px[i], py[i], pz[i]}, {nx[i], ny[i], nz[i]}, front_face[i], {ex[i], ey[i], ez[i]}};
  }
  constexpr void set(std::size_t i, const BasicSurface<S>& s) const {
    px[i] = s.point.x, py[i] = s.point.y, pz[i] = s.point.z;
    nx[i] = s.normal.x, ny[i] = s.normal.y, nz[i] = s.normal.z;
    front_face[i] = s.front_face;
    ex[i] = s.error.x, ey[i] = s.error.y, ez[i] = s.error.z;
  }
};

/// count directions or points, vector i being (x[i], y[i], z[i]).
template <Scalar S>
struct BasicVectorArrays {
  const S* x = nullptr;
  const S* y = nullptr;
  const S* z = nullptr;
  std::size_t count = 0;

  constexpr BasicVec3<S> at(std::size_t i) const { return {x[i], y[i], z[i]}; }
};

/// The same, written to.
template <Scalar S>
struct BasicVectorOutArrays {
  S* x = nullptr;
  S* y = nullptr;
  S* z = nullptr;
  std::size_t count = 0;

  constexpr void set(std::size_t i, BasicVec3<S> v) const { x[i] = v.x, y[i] = v.y, z[i] = v.z; }
};

using RayArrays = BasicRayArrays<float>;
using RayArraysd = BasicRayArrays<double>;
using HitArrays = BasicHitArrays<float>;
using HitArraysd = BasicHitArrays<double>;
using SurfaceArrays = BasicSurfaceArrays<float>;
using SurfaceArraysd = BasicSurfaceArrays<double>;
using VectorArrays = BasicVectorArrays<float>;
using VectorArraysd = BasicVectorArrays<double>;
using VectorOutArrays = BasicVectorOutArrays<float>;
using VectorOutArraysd = BasicVectorOutArrays<double>;

}  // namespace sphray
