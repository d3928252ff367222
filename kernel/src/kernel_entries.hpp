// The entry points of one instruction set's kernel, built from SphereBatchKernel<A>. A per-ISA
// unit includes this and defines its Kernel table with make_kernel<A>(isa).
#pragma once

#include <cstddef>

#include "kernel_table.hpp"
#include "sphere_batch.hpp"
#include "sphray/query.hpp"

namespace sphray::detail {

template <class A>
struct KernelEntries {
  using Batch = SphereBatchKernel<A>;

  // Below this many spheres the plain scalar loop wins: a batch's per-ray setup and the final
  // horizontal reduction cost more than the sphere tests they save (measured in
  // docs/performance.md), so tiny scenes are never slower than the reference.
  static constexpr std::size_t kScalarBelow = 8;

  static Hit intersect(SphereView v, const Ray& ray) {
    return v.count < kScalarBelow ? scalar::intersect(v, ray) : Batch::intersect(v, ray);
  }
  static bool occluded(SphereView v, const Ray& ray) {
    return v.count < kScalarBelow ? scalar::occluded(v, ray) : Batch::occluded(v, ray);
  }
  static void intersect_stream(SphereView v, const Ray* rays, Hit* hits, std::size_t n) {
    if (v.count < kScalarBelow) {
      for (std::size_t i = 0; i < n; ++i)
        hits[i] = scalar::intersect(v, rays[i]);
      return;
    }
    for (std::size_t i = 0; i < n; ++i)
      hits[i] = Batch::intersect(v, rays[i]);
  }
};

template <class A>
constexpr Kernel make_kernel(Isa isa) {
  using E = KernelEntries<A>;
  return {isa, E::Batch::kWidth, &E::intersect, &E::occluded, &E::intersect_stream};
}

}  // namespace sphray::detail
