#include "path/wavefront.hpp"

#include <cmath>
#include <iterator>

namespace sphray::render {
namespace {

// The copies of the passes this build has, best first (render/CMakeLists.txt).
constexpr ShadeClone kClones[] = {
#if SPHRAY_SHADE_HAS_AVX512
    {Isa::avx512, &avx512::shade, &avx512::start},
#endif
#if SPHRAY_SHADE_HAS_AVX2
    {Isa::avx2, &avx2::shade, &avx2::start},
#endif
#if SPHRAY_SHADE_HAS_SSE4_2
    {Isa::sse4_2, &sse4_2::shade, &sse4_2::start},
#endif
    {Isa::scalar, &baseline::shade, &baseline::start},
};

// The parts of AVX-512 the avx512 copy is compiled for, beyond the foundation the kernel's
// avx512 needs (every AVX-512 CPU but the Xeon Phi has them).
bool has_avx512_parts() {
#if SPHRAY_SHADE_HAS_AVX512
  return __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
         __builtin_cpu_supports("avx512bw");
#else
  return false;
#endif
}

// Whether a copy built for `clone` runs where the kernel runs `active`: x86's sets nest.
bool runs_on(Isa clone, Isa active) {
  switch (clone) {
    case Isa::avx512:
      return active == Isa::avx512 && has_avx512_parts();
    case Isa::avx2:
      return active == Isa::avx2 || active == Isa::avx512;
    case Isa::sse4_2:
      return active == Isa::sse4_2 || active == Isa::avx2 || active == Isa::avx512;
    default:
      return true;
  }
}

}  // namespace

ShadingTable::ShadingTable(const Scene& scene) : spheres_(scene.spheres.view()) {
  const auto lambertian = static_cast<std::int32_t>(MaterialKind::lambertian);
  rows_.resize(spheres_.count + 1, SphereShading{1, 1, 1, 0, 1, lambertian});
  for (std::uint32_t id = 0; id < spheres_.count; ++id) {
    const Material m = material_of(scene, id);
    const bool glass = m.kind == MaterialKind::dielectric;
    rows_[id] = {glass ? 1.0f : m.albedo.x,
                 glass ? 1.0f : m.albedo.y,
                 glass ? 1.0f : m.albedo.z,
                 m.fuzz,
                 m.ior,
                 static_cast<std::int32_t>(m.kind)};
  }
}

std::span<const ShadeClone> shade_clones() {
  return kClones;
}

const ShadeClone& clone_for(Isa active) {
  for (const ShadeClone& clone : kClones) {
    if (runs_on(clone.isa, active)) return clone;
  }
  return kClones[std::size(kClones) - 1];
}

}  // namespace sphray::render
