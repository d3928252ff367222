// Intel Embree 3 on the same spheres and rays: RTC_GEOMETRY_TYPE_SPHERE_POINT, one float4
// (x, y, z, r) per sphere, primID = sphray's sphere id.
#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "bench/embree_crossings.hpp"  // render/src/bench: the Embree glue `sphray bench` uses too
#include "bench/embree_spheres.hpp"
#include "implementations.hpp"
#include "threads.hpp"

namespace sphray::bench {
namespace {

// Bytes Embree holds right now, kept up to date by its memory monitor callback.
std::atomic<long long> embree_bytes{0};

bool count_bytes(void*, ssize_t bytes, bool) {
  embree_bytes += bytes;
  return true;
}

void fail_on_error(void*, RTCError code, const char* message) {
  std::fprintf(stderr, "Embree error %d: %s\n", static_cast<int>(code), message);
  std::abort();  // a benchmark of a failed build would report nonsense
}

RTCDevice device() {
  static const RTCDevice d = [] {
    RTCDevice dev = rtcNewDevice(nullptr);
    if (!dev) {
      std::fprintf(stderr, "rtcNewDevice failed\n");
      std::abort();
    }
    rtcSetDeviceErrorFunction(dev, fail_on_error, nullptr);
    rtcSetDeviceMemoryMonitorFunction(dev, count_bytes, nullptr);
    return dev;
  }();
  return d;
}

using SceneHandle = std::shared_ptr<RTCSceneTy>;

// A committed scene holding the spheres, built on `threads` threads, with an intersection
// filter on the spheres if one is given.
SceneHandle build_scene(const SphereSoA& spheres, int threads,
                        RTCFilterFunctionN intersect_filter = nullptr) {
  RTCScene scene = rtcNewScene(device());
  embree::attach_spheres(device(), scene, spheres.view(), intersect_filter);
  run_on_threads(threads, [&] { rtcCommitScene(scene); });
  return SceneHandle(scene, rtcReleaseScene);
}

// The scene tracing benchmarks use, built once per scene (both ray kinds share it).
SceneHandle scene_for(const Workload& w) {
  static std::string built_for;
  static SceneHandle scene;
  if (!scene || built_for != w.scene) {
    scene.reset();
    scene = build_scene(w.spheres, all_threads());
    built_for = w.scene;
  }
  return scene;
}

using embree::set_lane;
using embree::to_embree;

void occluded1(RTCScene scene, std::span<const Ray> rays, bool* blocked) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    RTCRay ray = to_embree(rays[i]).ray;
    rtcOccluded1(scene, &context, &ray);
    blocked[i] = ray.tfar == -INFINITY;  // Embree marks an occluded ray so
  }
}

template <std::size_t kLanes, class Packet,
          void (*kOccluded)(const int*, RTCScene, RTCIntersectContext*, Packet*)>
void occluded_packets(RTCScene scene, std::span<const Ray> rays, bool* blocked) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (std::size_t first = 0; first < rays.size(); first += kLanes) {
    Packet packet{};
    alignas(64) int valid[kLanes] = {};
    const std::size_t n = std::min<std::size_t>(kLanes, rays.size() - first);
    for (std::size_t k = 0; k < n; ++k) {
      valid[k] = -1;
      set_lane(packet, k, rays[first + k]);
    }
    kOccluded(valid, scene, &context, &packet);
    for (std::size_t k = 0; k < n; ++k)
      blocked[first + k] = packet.tfar[k] == -INFINITY;
  }
}

using EmbreeTrace = void (*)(RTCScene, std::span<const Ray>, std::span<Hit>);
using EmbreeOcclusion = void (*)(RTCScene, std::span<const Ray>, bool*);

Implementation embree(std::string name, EmbreeTrace fn, int threads) {
  auto prepare = [fn, threads](const Workload& w) -> Trace {
    return [fn, threads, scene = scene_for(w)](std::span<const Ray> rays, std::span<Hit> hits) {
      if (threads == 1) return fn(scene.get(), rays, hits);
      parallel_chunks(threads, rays.size(), [&](std::size_t begin, std::size_t end) {
        fn(scene.get(), rays.subspan(begin, end - begin), hits.subspan(begin, end - begin));
      });
    };
  };
  return {std::move(name), threads, false, 0, prepare};
}

Builder embree_builder(int threads) {
  auto prepare = [threads](const SphereSoA& spheres) -> std::function<Built()> {
    return [threads, &spheres] {
      const long long before = embree_bytes;
      SceneHandle scene = build_scene(spheres, threads);
      return Built{scene, static_cast<std::size_t>(embree_bytes - before)};
    };
  };
  return {"embree", threads, prepare};
}

}  // namespace

EmbreeCrossings::EmbreeCrossings(const SphereSoA& spheres, bool counting)
    : scene_(build_scene(spheres, 1, counting ? embree::count_only : embree::keep_nearest)) {}

std::size_t EmbreeCrossings::intersect_all(const Ray& ray, std::span<Hit> out) const {
  return embree::every_crossing(static_cast<RTCScene>(scene_.get()), ray, out);
}

std::vector<Implementation> embree_implementations() {
  std::vector<Implementation> impls;
  using embree::intersect1;
  using embree::intersect16;
  using embree::intersect8;
  impls.push_back(embree("embree-intersect1", intersect1, 1));
  if (all_threads() > 1) impls.push_back(embree("embree-intersect1", intersect1, all_threads()));
  if (rtcGetDeviceProperty(device(), RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED)) {
    impls.push_back(embree("embree-intersect8", intersect8, 1));
    if (all_threads() > 1) impls.push_back(embree("embree-intersect8", intersect8, all_threads()));
  }
  if (rtcGetDeviceProperty(device(), RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)) {
    impls.push_back(embree("embree-intersect16", intersect16, 1));
    if (all_threads() > 1)
      impls.push_back(embree("embree-intersect16", intersect16, all_threads()));
  }
  return impls;
}

std::vector<Occluder> embree_occluders() {
  const auto make = [](std::string name, EmbreeOcclusion fn) {
    return Occluder{std::move(name), [fn](const Workload& w) -> Occlusion {
                      return [fn, scene = scene_for(w)](std::span<const Ray> rays, bool* blocked) {
                        fn(scene.get(), rays, blocked);
                      };
                    }};
  };
  std::vector<Occluder> occluders{make("embree-occluded1", occluded1)};
  if (rtcGetDeviceProperty(device(), RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED))
    occluders.push_back(make("embree-occluded8", occluded_packets<8, RTCRay8, rtcOccluded8>));
  if (rtcGetDeviceProperty(device(), RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED))
    occluders.push_back(make("embree-occluded16", occluded_packets<16, RTCRay16, rtcOccluded16>));
  return occluders;
}

std::vector<Builder> embree_builders() {
  std::vector<Builder> builders{embree_builder(1)};
  if (all_threads() > 1) builders.push_back(embree_builder(all_threads()));
  return builders;
}

}  // namespace sphray::bench
