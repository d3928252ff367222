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
struct RayArrays {
  const float* ox = nullptr;
  const float* oy = nullptr;
  const float* oz = nullptr;
  const float* dx = nullptr;
  const float* dy = nullptr;
  const float* dz = nullptr;
  const float* tmin = nullptr;
  const float* tmax = nullptr;
  const std::uint32_t* mask = nullptr;
  std::size_t count = 0;

  /// Ray i as a Ray.
  constexpr Ray at(std::size_t i) const {
    return {{ox[i], oy[i], oz[i]},
            {dx[i], dy[i], dz[i]},
            tmin != nullptr ? tmin[i] : 0.0f,
            tmax != nullptr ? tmax[i] : INFINITY,
            mask != nullptr ? mask[i] : kAllBits};
  }
};

/// count hits: hit i is {t[i], id[i]}, as Hit (id kNoHit and t the ray's tmax for a miss).
struct HitArrays {
  float* t = nullptr;
  std::uint32_t* id = nullptr;
  std::size_t count = 0;

  constexpr Hit at(std::size_t i) const { return {t[i], id[i]}; }
  constexpr void set(std::size_t i, const Hit& hit) const {
    t[i] = hit.t;
    id[i] = hit.id;
  }
};

/// count surfaces, surface i being {point (px[i], py[i], pz[i]), normal (nx[i], ny[i], nz[i]),
/// front_face[i], error (ex[i], ey[i], ez[i])}: what surfaces() writes (query.hpp) and
/// offset_origins() reads. Every array holds count values.
struct SurfaceArrays {
  float* px = nullptr;
  float* py = nullptr;
  float* pz = nullptr;
  float* nx = nullptr;
  float* ny = nullptr;
  float* nz = nullptr;
  bool* front_face = nullptr;
  float* ex = nullptr;
  float* ey = nullptr;
  float* ez = nullptr;
  std::size_t count = 0;

  constexpr Surface at(std::size_t i) const {
    return {{px[i], py[i], pz[i]}, {nx[i], ny[i], nz[i]}, front_face[i], {ex[i], ey[i], ez[i]}};
  }
  constexpr void set(std::size_t i, const Surface& s) const {
    px[i] = s.point.x, py[i] = s.point.y, pz[i] = s.point.z;
    nx[i] = s.normal.x, ny[i] = s.normal.y, nz[i] = s.normal.z;
    front_face[i] = s.front_face;
    ex[i] = s.error.x, ey[i] = s.error.y, ez[i] = s.error.z;
  }
};

/// count directions or points, vector i being (x[i], y[i], z[i]).
struct VectorArrays {
  const float* x = nullptr;
  const float* y = nullptr;
  const float* z = nullptr;
  std::size_t count = 0;

  constexpr Vec3 at(std::size_t i) const { return {x[i], y[i], z[i]}; }
};

/// The same, written to.
struct VectorOutArrays {
  float* x = nullptr;
  float* y = nullptr;
  float* z = nullptr;
  std::size_t count = 0;

  constexpr void set(std::size_t i, Vec3 v) const { x[i] = v.x, y[i] = v.y, z[i] = v.z; }
};

}  // namespace sphray
