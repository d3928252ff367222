#include "bench/bench_rows.hpp"

#include <memory>

#include "bench/tree_cache.hpp"
#include "dispatch/entry_table.hpp"  // each instruction set's brute force (sphray_kernel_internals)

namespace sphray::render::bench {
namespace {

using detail::EntryTable;

Row scalar_brute_force() {
  auto prepare = [](SphereView spheres) -> Trace {
    return [spheres](std::span<const Ray> rays, std::span<Hit> hits) {
      for (std::size_t i = 0; i < rays.size(); ++i)
        hits[i] = scalar::intersect(spheres, rays[i]);
    };
  };
  return {"scalar brute force", true, true, false, prepare};
}

// The public brute force goes through a view-size rule to a narrower kernel for tiny views; a
// row per instruction set shows each kernel itself.
Row brute_force(const EntryTable& kernel, bool dispatched) {
  auto prepare = [&kernel](SphereView spheres) -> Trace {
    return [&kernel, spheres](std::span<const Ray> rays, std::span<Hit> hits) {
      for (std::size_t i = 0; i < rays.size(); ++i)
        hits[i] = kernel.intersect(spheres, rays[i]);
    };
  };
  return {std::string(isa_name(kernel.isa)) + " brute force", true, true, dispatched, prepare};
}

// An instruction set's brute force with the rays across its lanes, whatever the scene's size: the
// stream on a view takes it for few spheres (the query plan's rule 9), these rows show where.
Row rays_across(const EntryTable& kernel) {
  auto prepare = [&kernel](SphereView spheres) -> Trace {
    return [&kernel, spheres](std::span<const Ray> rays, std::span<Hit> hits) {
      kernel.intersect_across(spheres, rays.data(), hits.data(), rays.size());
    };
  };
  return {std::string(isa_name(kernel.isa)) + " rays across", true, true, false, prepare};
}

// The stream call on the spheres themselves, as the renderer makes it on small scenes.
Row brute_force_stream() {
  auto prepare = [](SphereView spheres) -> Trace {
    return [spheres](std::span<const Ray> rays, std::span<Hit> hits) {
      intersect(spheres, rays, hits);
    };
  };
  return {"brute force stream", true, true, true, prepare};
}

// The tree and stream rows of an instruction set share one build (TreeCache): the tree row
// builds it, the stream row takes it over.
Row tree_per_ray(const std::shared_ptr<TreeCache>& cache, bool chosen) {
  auto prepare = [cache](SphereView spheres) -> Trace {
    return [tree = cache->get(spheres)](std::span<const Ray> rays, std::span<Hit> hits) {
      for (std::size_t i = 0; i < rays.size(); ++i)
        hits[i] = intersect(*tree, rays[i]);
    };
  };
  return {std::string(isa_name(*cache->isa())) + " tree", false, true, chosen, prepare};
}

Row tree_stream(const std::shared_ptr<TreeCache>& cache, bool chosen) {
  auto prepare = [cache](SphereView spheres) -> Trace {
    return [tree = cache->take(spheres)](std::span<const Ray> rays, std::span<Hit> hits) {
      intersect(*tree, rays, hits);
    };
  };
  return {std::string(isa_name(*cache->isa())) + " stream", false, true, chosen, prepare};
}

}  // namespace

std::string supported_isa_list() {
  std::string list;
  for (Isa isa : supported_isas()) {
    if (!list.empty()) list += ' ';
    list += isa_name(isa);
  }
  return list;
}

std::vector<Row> sphray_rows(std::size_t sphere_count) {
  std::vector<Row> rows;
  const Isa brute_isa = detail::entries_for_size(sphere_count).isa;
  rows.push_back(scalar_brute_force());
  for (Isa isa : supported_isas())
    if (isa != Isa::scalar)
      rows.push_back(brute_force(*detail::find_entries(isa), isa == brute_isa));
  for (Isa isa : supported_isas())
    if (isa != Isa::scalar) rows.push_back(rays_across(*detail::find_entries(isa)));
  rows.push_back(brute_force_stream());
  if (sphere_count > kBruteForceUpTo) {
    for (Row& row : rows)
      row.skipped = "brute force is timed up to " + std::to_string(kBruteForceUpTo) +
                    " spheres, this scene has " + std::to_string(sphere_count) +
                    " (every ray would test every sphere: the tree rows answer the same rays)";
  }
  const Isa tree_isa = bvh_isa(sphere_count);  // what a tree of this scene takes by default
  for (Isa isa : supported_isas()) {
    auto cache = std::make_shared<TreeCache>(isa);
    rows.push_back(tree_per_ray(cache, isa == tree_isa));
    if (isa != Isa::scalar) rows.push_back(tree_stream(cache, isa == tree_isa));
  }
  return rows;
}

}  // namespace sphray::render::bench
