// Intel Embree 3 on the same spheres and rays, where the build has it (SPHRAY_WITH_EMBREE): the
// closest hit through embree_spheres.hpp, every crossing through its multi-hit filters
// (embree_crossings.hpp). Linked into the sphray command only, never into the kernel.
#include "bench/bench_crossings.hpp"
#include "bench/bench_rows.hpp"

#if SPHRAY_WITH_EMBREE
#include <memory>
#include <stdexcept>

#include "bench/embree_crossings.hpp"
#include "bench/embree_spheres.hpp"
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

SceneHandle build_scene(SphereView spheres, RTCFilterFunctionN intersect_filter = nullptr) {
  RTCScene scene = rtcNewScene(device().get());
  embree::attach_spheres(device().get(), scene, spheres, intersect_filter);
  rtcCommitScene(scene);
  return SceneHandle(scene, rtcReleaseScene);
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

// A multi-hit filter's row: with keep_nearest the 16 nearest and the total, with count_only the
// total alone.
CrossingRow embree_crossing_row(std::string name, bool counting, std::string same_answer_as) {
  CrossingRow row{std::move(name), counting, false, false, std::move(same_answer_as), {}, {}};
  row.prepare = [counting](SphereView spheres) -> CrossingTrace {
    SceneHandle scene = build_scene(spheres, counting ? embree::count_only : embree::keep_nearest);
    return [scene](std::span<const Ray> rays, std::span<std::size_t> totals, std::span<Hit> lists) {
      for (std::size_t i = 0; i < rays.size(); ++i)
        totals[i] = embree::every_crossing(
            scene.get(), rays[i],
            lists.empty() ? std::span<Hit>() : lists.subspan(i * kCrossingRoom, kCrossingRoom));
    };
  };
  return row;
}

}  // namespace

std::vector<CrossingRow> embree_crossing_rows() {
  std::vector<CrossingRow> rows;
  rows.push_back(embree_crossing_row("embree filter count", true, "tree count_hits"));
  rows.push_back(embree_crossing_row("embree filter all16", false, "tree intersect_all16"));
  return rows;
}

std::vector<Row> embree_rows() {
  std::vector<Row> rows{embree_row("embree rtcIntersect1", embree::intersect1),
                        embree_row("embree rtcIntersect8", embree::intersect8),
                        embree_row("embree rtcIntersect16", embree::intersect16)};
  if (!rtcGetDeviceProperty(device().get(), RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED))
    rows[1].skipped = "this Embree has no native packets of 8 rays";
  if (!rtcGetDeviceProperty(device().get(), RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED))
    rows[2].skipped = "this Embree has no native packets of 16 rays (it needs AVX-512)";
  return rows;
}

std::string embree_version() {
  return "Embree " RTC_VERSION_STRING;
}
#else
std::vector<Row> embree_rows() {
  return {};
}

std::vector<CrossingRow> embree_crossing_rows() {
  return {};
}

std::string embree_version() {
  return {};
}
#endif

}  // namespace sphray::render::bench
