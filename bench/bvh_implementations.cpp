// sphray::SphereBVH, the accelerated path for large scenes, through the public API only.
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

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

// Rays and hits as arrays per quantity (sphray/ray_arrays.hpp), kept for one set of rays.
struct Columns {
  std::vector<float> ox, oy, oz, dx, dy, dz, tmin, tmax, t;
  std::vector<std::uint32_t> mask, id;

  explicit Columns(std::span<const Ray> rays) {
    for (const Ray& r : rays) {
      ox.push_back(r.origin.x), oy.push_back(r.origin.y), oz.push_back(r.origin.z);
      dx.push_back(r.dir.x), dy.push_back(r.dir.y), dz.push_back(r.dir.z);
      tmin.push_back(r.tmin), tmax.push_back(r.tmax), mask.push_back(r.mask);
    }
    t.resize(rays.size());
    id.resize(rays.size());
  }
  RayArrays rays() const {
    return {ox.data(), oy.data(),   oz.data(),   dx.data(),   dy.data(),
            dz.data(), tmin.data(), tmax.data(), mask.data(), ox.size()};
  }
  HitArrays hits() { return {t.data(), id.data(), t.size()}; }
};

// The stream with the rays as arrays per quantity, as a wavefront tracer keeps them: the
// arrays are made before the timed loop (for the rays it traces and for the check's sample);
// inside it, the hits are copied back into Hits for the benchmark, a cost the Ray call does
// not pay.
Implementation stream_arrays() {
  auto prepare = [](const Workload& w) -> Trace {
    auto columns = std::make_shared<std::map<const Ray*, Columns>>();
    columns->emplace(w.rays.data(), Columns(w.rays));
    columns->emplace(w.sample.data(), Columns(w.sample));
    return [bvh = bvh_for(w), columns](std::span<const Ray> rays, std::span<Hit> hits) {
      auto it = columns->find(rays.data());
      if (it == columns->end() || it->second.ox.size() != rays.size())
        it = columns->insert_or_assign(rays.data(), Columns(rays)).first;
      Columns& c = it->second;
      intersect(*bvh, c.rays(), c.hits());
      for (std::size_t i = 0; i < rays.size(); ++i)
        hits[i] = {c.t[i], c.id[i]};
    };
  };
  return {"bvh-arrays", 1, false, 0, prepare};
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
  std::vector<Implementation> impls{per_ray(), stream(1), stream_arrays()};
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
