// Intel Embree 3 on sphray's spheres and rays, for the comparisons (`sphray bench` and the
// bench/ program): RTC_GEOMETRY_TYPE_SPHERE_POINT, one float4 (x, y, z, r) per sphere, primID =
// sphray's sphere id, and the closest hit of single rays and of 8- and 16-wide packets. Never
// part of the kernel or the render library: only what is built with Embree includes it.
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>
#include <cstddef>
#include <span>

#include "sphray/sphray.hpp"

namespace sphray::embree {

/// The spheres as one committed geometry of the scene (which the caller commits), with an
/// intersection filter if one is given (Embree calls it on every hit it finds).
inline void attach_spheres(RTCDevice device, RTCScene scene, const SphereView& spheres,
                           RTCFilterFunctionN intersect_filter = nullptr) {
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  auto* xyzr = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), spheres.count));
  for (std::size_t i = 0; i < spheres.count; ++i) {
    xyzr[4 * i + 0] = spheres.cx[i];
    xyzr[4 * i + 1] = spheres.cy[i];
    xyzr[4 * i + 2] = spheres.cz[i];
    xyzr[4 * i + 3] = spheres.radius[i];
  }
  if (intersect_filter) rtcSetGeometryIntersectFilterFunction(geometry, intersect_filter);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
}

/// Fills lane k of a packet of rays (RTCRay8, RTCRay16) from ray.
template <class Rays>
void set_lane(Rays& out, std::size_t k, const Ray& ray) {
  out.org_x[k] = ray.origin.x;
  out.org_y[k] = ray.origin.y;
  out.org_z[k] = ray.origin.z;
  out.dir_x[k] = ray.dir.x;
  out.dir_y[k] = ray.dir.y;
  out.dir_z[k] = ray.dir.z;
  out.tnear[k] = ray.tmin;
  out.tfar[k] = ray.tmax;
  out.mask[k] = ~0u;
}

inline RTCRayHit to_embree(const Ray& ray) {
  RTCRayHit rh{};
  rh.ray.org_x = ray.origin.x;
  rh.ray.org_y = ray.origin.y;
  rh.ray.org_z = ray.origin.z;
  rh.ray.dir_x = ray.dir.x;
  rh.ray.dir_y = ray.dir.y;
  rh.ray.dir_z = ray.dir.z;
  rh.ray.tnear = ray.tmin;
  rh.ray.tfar = ray.tmax;
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

inline Hit from_embree(unsigned geom_id, float tfar, unsigned prim_id, const Ray& ray) {
  return geom_id == RTC_INVALID_GEOMETRY_ID ? Hit{ray.tmax, kNoHit} : Hit{tfar, prim_id};
}

/// hits[i] for rays[i], one rtcIntersect1 each.
inline void intersect1(RTCScene scene, std::span<const Ray> rays, std::span<Hit> hits) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    RTCRayHit rh = to_embree(rays[i]);
    rtcIntersect1(scene, &context, &rh);
    hits[i] = from_embree(rh.hit.geomID, rh.ray.tfar, rh.hit.primID, rays[i]);
  }
}

/// The same in packets of kLanes consecutive rays (8 or 16): neighbouring pixels for camera
/// rays, as a renderer hands them to Embree.
template <std::size_t kLanes, class Packet,
          void (*kIntersect)(const int*, RTCScene, RTCIntersectContext*, Packet*)>
void intersect_packets(RTCScene scene, std::span<const Ray> rays, std::span<Hit> hits) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (std::size_t first = 0; first < rays.size(); first += kLanes) {
    Packet packet{};
    alignas(64) int valid[kLanes] = {};
    const std::size_t n = std::min<std::size_t>(kLanes, rays.size() - first);
    for (std::size_t k = 0; k < n; ++k) {
      valid[k] = -1;
      set_lane(packet.ray, k, rays[first + k]);
      packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    kIntersect(valid, scene, &context, &packet);
    for (std::size_t k = 0; k < n; ++k)
      hits[first + k] = from_embree(packet.hit.geomID[k], packet.ray.tfar[k], packet.hit.primID[k],
                                    rays[first + k]);
  }
}

inline constexpr auto intersect8 = intersect_packets<8, RTCRayHit8, rtcIntersect8>;
inline constexpr auto intersect16 = intersect_packets<16, RTCRayHit16, rtcIntersect16>;

}  // namespace sphray::embree
