// The queries: closest hit, any hit, a stream of closest hits, and the surface at a hit.
//
// Contract (all instruction sets and the scalar reference alike):
// - Sphere i is hit at t when tmin < t < tmax. Of its two roots the near one is taken when it
//   lies in that interval, else the far one: a ray starting inside a sphere hits its far side.
// - intersect returns the smallest such t over all spheres and that sphere's id; equal t from
//   two spheres: the lower id. On a miss, id == kNoHit and t == ray.tmax.
// - A sphere with a NaN or infinite centre component, or a radius whose square is not a normal
//   finite float (NaN, <= 0, below 2^-63 ~ 1.08e-19, or from 2^64 ~ 1.8e19 on), is never hit
//   (docs/kernel.md, "Contract"). A ray with a NaN or
//   infinite origin or direction component, a zero direction (or one whose squared length
//   overflows or underflows float), a NaN bound, or !(tmin < tmax) misses everything.
// - A ray sees sphere i only if SphereView::mask[i] (every bit if the view has no masks) and
//   ray.mask share a bit; a ray whose mask is 0 misses everything.
// - Queries never allocate, lock, throw (but for the stream calls' argument checks) or touch
//   mutable global state: any number of threads may query the same spheres at once.
#pragma once

#include <span>

#include "sphray/api.h"
#include "sphray/ray.hpp"
#include "sphray/ray_arrays.hpp"
#include "sphray/spheres.hpp"

namespace sphray {

/// Closest hit of ray among spheres, on the instruction set active_isa() names.
SPHRAY_API Hit intersect(SphereView spheres, const Ray& ray);

/// True if any sphere is hit in (tmin, tmax); returns at the first hit found.
SPHRAY_API bool occluded(SphereView spheres, const Ray& ray);

/// hits[i] = intersect(spheres, rays[i]). Throws std::length_error unless
/// hits.size() == rays.size().
SPHRAY_API void intersect(SphereView spheres, std::span<const Ray> rays, std::span<Hit> hits);

/// The same stream with rays and hits as arrays per quantity: hit i (hits.t[i], hits.id[i]) is
/// intersect(spheres, rays.at(i)), bit for bit. Throws std::length_error unless
/// hits.count == rays.count, std::invalid_argument if a ray's origin or direction array or a
/// hit array is null while count > 0.
SPHRAY_API void intersect(SphereView spheres, const RayArrays& rays, const HitArrays& hits);

/// blocked[i] = occluded(spheres, rays[i]). Throws std::length_error unless
/// blocked.size() == rays.size().
SPHRAY_API void occluded(SphereView spheres, std::span<const Ray> rays, std::span<bool> blocked);

/// The surface where hit meets ray: the point re-projected onto the sphere and the outward
/// unit normal. For a miss (!hit.found()) or an id outside the view: point = ray.at(hit.t),
/// normal = {0, 0, 0}, front_face = false.
SPHRAY_API Surface surface(SphereView spheres, const Ray& ray, const Hit& hit);

/// The ray leaving surface along dir (any length, not zero): its origin is surface.point moved
/// along the normal, to the side dir points to, just past surface.error, so that a ray leaving
/// outward (dot(dir, normal) > 0) never meets the sphere it leaves again, and one leaving inward
/// meets the sphere's far side, never the point it starts from. tmin = 0, tmax = infinity.
/// The guarantee and its limits: docs/kernel.md, "Leaving a surface". A surface from a miss
/// (zero normal and error) gives the ray from surface.point.
SPHRAY_API Ray spawn(const Surface& surface, Vec3 dir);

/// The origin of spawn(surface, dir), for callers that build their own rays (pbrt-v4's
/// OffsetRayOrigin).
SPHRAY_API Vec3 offset_origin(const Surface& surface, Vec3 dir);

/// surface() for a stream: surface i of out is surface(spheres, rays.at(i), hits.at(i)), bit for
/// bit, on the instruction set active_isa() names. The hits are only read. Throws
/// std::length_error unless hits.count and out.count equal rays.count, std::invalid_argument if
/// an array but tmin, tmax and mask is null while count > 0.
SPHRAY_API void surfaces(SphereView spheres, const RayArrays& rays, const HitArrays& hits,
                         const SurfaceArrays& out);

/// offset_origin() for a stream: origin i is offset_origin(surfaces.at(i), dirs.at(i)), bit
/// for bit. Throws std::length_error unless dirs.count and origins.count equal surfaces.count,
/// std::invalid_argument if an array is null while count > 0.
SPHRAY_API void offset_origins(const SurfaceArrays& surfaces, const VectorArrays& dirs,
                               const VectorOutArrays& origins);

/// The queries in double precision (docs/double.md): the same contract, with double's range in
/// place of float's (a ray's squared direction length and a sphere's squared radius normal,
/// finite doubles: radii from 2^-511 to below 2^512), on double's SIMD lanes.
SPHRAY_API Hitd intersect(SphereViewd spheres, const Rayd& ray);
SPHRAY_API bool occluded(SphereViewd spheres, const Rayd& ray);
SPHRAY_API void intersect(SphereViewd spheres, std::span<const Rayd> rays, std::span<Hitd> hits);
SPHRAY_API void intersect(SphereViewd spheres, const RayArraysd& rays, const HitArraysd& hits);
SPHRAY_API void occluded(SphereViewd spheres, std::span<const Rayd> rays, std::span<bool> blocked);
SPHRAY_API Surfaced surface(SphereViewd spheres, const Rayd& ray, const Hitd& hit);
SPHRAY_API Rayd spawn(const Surfaced& surface, Vec3d dir);
SPHRAY_API Vec3d offset_origin(const Surfaced& surface, Vec3d dir);
SPHRAY_API void surfaces(SphereViewd spheres, const RayArraysd& rays, const HitArraysd& hits,
                         const SurfaceArraysd& out);
SPHRAY_API void offset_origins(const SurfaceArraysd& surfaces, const VectorArraysd& dirs,
                               const VectorOutArraysd& origins);

/// The reference implementation: the same contract in plain C++, one sphere at a time.
namespace scalar {
SPHRAY_API Hit intersect(SphereView spheres, const Ray& ray);
SPHRAY_API bool occluded(SphereView spheres, const Ray& ray);
SPHRAY_API Hitd intersect(SphereViewd spheres, const Rayd& ray);
SPHRAY_API bool occluded(SphereViewd spheres, const Rayd& ray);
}  // namespace scalar

}  // namespace sphray
