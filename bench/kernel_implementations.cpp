// sphray's own implementations, through the public API only.
#include "implementations.hpp"
#include "threads.hpp"

namespace sphray::bench {
namespace {

using RayFn = Hit (*)(SphereView, const Ray&);

// One query per ray, in order.
Implementation per_ray(std::string name, RayFn fn, std::size_t width) {
  auto prepare = [fn](const Workload& w) -> Trace {
    return [fn, view = w.view()](std::span<const Ray> rays, std::span<Hit> hits) {
      for (std::size_t i = 0; i < rays.size(); ++i)
        hits[i] = fn(view, rays[i]);
    };
  };
  return {std::move(name), 1, true, width, prepare};
}

// A kernel's own stream entry point, one thread.
Implementation isa_stream(const EntryTable& kernel) {
  auto prepare = [&kernel](const Workload& w) -> Trace {
    return [&kernel, view = w.view()](std::span<const Ray> rays, std::span<Hit> hits) {
      kernel.intersect_stream(view, rays.data(), hits.data(), rays.size());
    };
  };
  return {std::string(isa_name(kernel.isa)) + "-stream", 1, true, kernel.width, prepare};
}

// A kernel's brute force with the rays across its lanes (a batch of rays per sphere), whatever
// the scene's size, one thread: the view stream takes it for few spheres (QueryPlan::rays_across).
Implementation isa_across(const EntryTable& kernel) {
  auto prepare = [&kernel](const Workload& w) -> Trace {
    return [&kernel, view = w.view()](std::span<const Ray> rays, std::span<Hit> hits) {
      kernel.intersect_across(view, rays.data(), hits.data(), rays.size());
    };
  };
  return {std::string(isa_name(kernel.isa)) + "-across", 1, true, 0, prepare};
}

// The dispatched stream query, the span split across threads by the caller.
Implementation dispatched_stream(int threads) {
  auto prepare = [threads](const Workload& w) -> Trace {
    return [threads, view = w.view()](std::span<const Ray> rays, std::span<Hit> hits) {
      parallel_chunks(threads, rays.size(), [&](std::size_t begin, std::size_t end) {
        intersect(view, rays.subspan(begin, end - begin), hits.subspan(begin, end - begin));
      });
    };
  };
  return {"dispatch-stream", threads, true, 0, prepare};
}

}  // namespace

std::vector<Implementation> kernel_implementations() {
  std::vector<Implementation> impls;
  impls.push_back(per_ray("scalar", &scalar::intersect, 1));
  for (Isa isa : supported_isas()) {
    if (isa == Isa::scalar) continue;
    const EntryTable& kernel = *find_entries(isa);
    impls.push_back(per_ray(std::string(isa_name(isa)), kernel.intersect, kernel.width));
    impls.push_back(isa_stream(kernel));
    impls.push_back(isa_across(kernel));
  }
  impls.push_back(per_ray("dispatch", static_cast<RayFn>(&intersect), 0));
  impls.push_back(dispatched_stream(1));
  if (all_threads() > 1) impls.push_back(dispatched_stream(all_threads()));
  return impls;
}

}  // namespace sphray::bench
