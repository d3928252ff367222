// sphray::SphereBVH, the accelerated path for large scenes, through the public API only.
#include <memory>
#include <string>

#include "implementations.hpp"
#include "threads.hpp"

namespace sphray::bench {
namespace {

using BvhHandle = std::shared_ptr<const SphereBVH>;

// The tree the tracing benchmarks use, built once per scene (both ray kinds share it).
BvhHandle bvh_for(const Workload& w) {
  static std::string built_for;
  static BvhHandle bvh;
  if (!bvh || built_for != w.scene) {
    bvh.reset();
    bvh = std::make_shared<const SphereBVH>(w.view());
    built_for = w.scene;
  }
  return bvh;
}

Implementation per_ray() {
  auto prepare = [](const Workload& w) -> Trace {
    return [bvh = bvh_for(w)](std::span<const Ray> rays, std::span<Hit> hits) {
      for (std::size_t i = 0; i < rays.size(); ++i)
        hits[i] = intersect(*bvh, rays[i]);
    };
  };
  return {"bvh", 1, false, 0, prepare};
}

Implementation stream(int threads) {
  auto prepare = [threads](const Workload& w) -> Trace {
    return [threads, bvh = bvh_for(w)](std::span<const Ray> rays, std::span<Hit> hits) {
      parallel_chunks(threads, rays.size(), [&](std::size_t begin, std::size_t end) {
        intersect(*bvh, rays.subspan(begin, end - begin), hits.subspan(begin, end - begin));
      });
    };
  };
  return {"bvh-stream", threads, false, 0, prepare};
}

Builder build(int threads) {
  auto prepare = [threads](const SphereSoA& spheres) -> std::function<Built()> {
    return [threads, view = spheres.view()] {
      BvhBuildOptions options;
      options.threads = static_cast<unsigned>(threads);
      std::shared_ptr<SphereBVH> bvh;
      run_on_threads(threads, [&] { bvh = std::make_shared<SphereBVH>(view, options); });
      return Built{bvh, bvh->memory_bytes()};
    };
  };
  return {"bvh", threads, prepare};
}

// Refit after the spheres moved: the same spheres, the same tree shape, new boxes. The
// spheres do not really move here; the work is the same.
Builder refit(int threads) {
  auto prepare = [threads](const SphereSoA& spheres) -> std::function<Built()> {
    auto bvh = std::make_shared<SphereBVH>(spheres.view());
    return [threads, bvh, view = spheres.view()] {
      run_on_threads(threads, [&] { bvh->refit(view); });
      return Built{bvh, bvh->memory_bytes()};
    };
  };
  return {"bvh-refit", threads, prepare};
}

}  // namespace

std::vector<Implementation> bvh_implementations() {
  std::vector<Implementation> impls{per_ray(), stream(1)};
  if (all_threads() > 1) impls.push_back(stream(all_threads()));
  return impls;
}

std::vector<Builder> bvh_builders() {
  std::vector<Builder> builders{build(1)};
  if (all_threads() > 1) builders.push_back(build(all_threads()));
  builders.push_back(refit(1));
  if (all_threads() > 1) builders.push_back(refit(all_threads()));
  return builders;
}

}  // namespace sphray::bench
