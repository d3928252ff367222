// Intel Embree 3 on the same spheres and rays, where the build has it (SPHRAY_WITH_EMBREE):
// RTC_GEOMETRY_TYPE_SPHERE_POINT, one float4 (x, y, z, r) per sphere, primID = sphray's id.
// Linked into the sphray command only, never into the kernel.
#include "bench_rows.hpp"

#if SPHRAY_WITH_EMBREE
#include <embree3/rtcore.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#endif

namespace sphray::render::bench {

#if SPHRAY_WITH_EMBREE
namespace {

void throw_on_error(void*, RTCError code, const char* message) {
  throw std::runtime_error("Embree error " + std::to_string(static_cast<int>(code)) + ": " +
                           (message != nullptr ? message : ""));
}

std::shared_ptr<RTCDeviceTy> device() {
  static const std::shared_ptr<RTCDeviceTy> d = [] {
    RTCDevice dev = rtcNewDevice(nullptr);
    if (dev == nullptr) throw std::runtime_error("Embree: rtcNewDevice failed");
    rtcSetDeviceErrorFunction(dev, throw_on_error, nullptr);
    return std::shared_ptr<RTCDeviceTy>(dev, rtcReleaseDevice);
  }();
  return d;
}

using SceneHandle = std::shared_ptr<RTCSceneTy>;

SceneHandle build_scene(SphereView spheres) {
  RTCScene scene = rtcNewScene(device().get());
  RTCGeometry geometry = rtcNewGeometry(device().get(), RTC_GEOMETRY_TYPE_SPHERE_POINT);
  auto* xyzr = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), spheres.count));
  for (std::size_t i = 0; i < spheres.count; ++i) {
    xyzr[4 * i + 0] = spheres.cx[i];
    xyzr[4 * i + 1] = spheres.cy[i];
    xyzr[4 * i + 2] = spheres.cz[i];
    xyzr[4 * i + 3] = spheres.radius[i];
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene);
  return SceneHandle(scene, rtcReleaseScene);
}

void intersect1(RTCScene scene, std::span<const Ray> rays, std::span<Hit> hits) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Ray& ray = rays[i];
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
    rtcIntersect1(scene, &context, &rh);
    hits[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? Hit{ray.tmax, kNoHit}
                                                       : Hit{rh.ray.tfar, rh.hit.primID};
  }
}

// Packets of N consecutive rays: neighbouring pixels for camera rays.
template <int N, class Packet, class Call>
void intersect_packets(RTCScene scene, std::span<const Ray> rays, std::span<Hit> hits, Call call) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (std::size_t first = 0; first < rays.size(); first += N) {
    alignas(64) Packet packet{};
    alignas(64) int valid[N] = {};
    const std::size_t n = std::min<std::size_t>(N, rays.size() - first);
    for (std::size_t k = 0; k < n; ++k) {
      const Ray& ray = rays[first + k];
      valid[k] = -1;
      packet.ray.org_x[k] = ray.origin.x;
      packet.ray.org_y[k] = ray.origin.y;
      packet.ray.org_z[k] = ray.origin.z;
      packet.ray.dir_x[k] = ray.dir.x;
      packet.ray.dir_y[k] = ray.dir.y;
      packet.ray.dir_z[k] = ray.dir.z;
      packet.ray.tnear[k] = ray.tmin;
      packet.ray.tfar[k] = ray.tmax;
      packet.ray.mask[k] = ~0u;
      packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    call(valid, scene, &context, &packet);
    for (std::size_t k = 0; k < n; ++k) {
      const Ray& ray = rays[first + k];
      hits[first + k] = packet.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID
                            ? Hit{ray.tmax, kNoHit}
                            : Hit{packet.ray.tfar[k], packet.hit.primID[k]};
    }
  }
}

void intersect8(RTCScene scene, std::span<const Ray> rays, std::span<Hit> hits) {
  intersect_packets<8, RTCRayHit8>(scene, rays, hits, rtcIntersect8);
}

void intersect16(RTCScene scene, std::span<const Ray> rays, std::span<Hit> hits) {
  intersect_packets<16, RTCRayHit16>(scene, rays, hits, rtcIntersect16);
}

using EmbreeTrace = void (*)(RTCScene, std::span<const Ray>, std::span<Hit>);

Row embree_row(std::string name, EmbreeTrace trace) {
  auto prepare = [trace](SphereView spheres) -> Trace {
    return [trace, scene = build_scene(spheres)](std::span<const Ray> rays, std::span<Hit> hits) {
      trace(scene.get(), rays, hits);
    };
  };
  return {std::move(name), false, false, false, prepare};
}

}  // namespace

std::vector<Row> embree_rows() {
  std::vector<Row> rows{embree_row("embree rtcIntersect1", intersect1)};
  if (rtcGetDeviceProperty(device().get(), RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED))
    rows.push_back(embree_row("embree rtcIntersect8", intersect8));
  if (rtcGetDeviceProperty(device().get(), RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED))
    rows.push_back(embree_row("embree rtcIntersect16", intersect16));
  return rows;
}

std::string embree_version() {
  return "Embree " RTC_VERSION_STRING;
}
#else
std::vector<Row> embree_rows() {
  return {};
}

std::string embree_version() {
  return {};
}
#endif

}  // namespace sphray::render::bench
