// The path tracer's wavefront: a tile's live paths as one array per quantity, and their shading
// (sphray::surface, scatter and sphray::spawn of material.hpp and sphray/query.hpp, for a whole
// wavefront) in passes over those arrays. The float passes are plain loops without calls or
// branches, which GCC vectorises; the build compiles them once per instruction set and the
// tracer runs the widest copy (clone_for). The random draws come from each path's counter: the
// camera's and each bounce's first ones for all lanes in a loop, the rest (after a rejected
// point of the disk, a dielectric's) one lane at a time. Every path gets the same float
// operations and the same draws in the same order as the one-path functions, so the images are
// the same bit for bit (tests/render/wavefront_test.cpp compares them lane by lane).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "sphray/render/camera.hpp"
#include "sphray/render/material.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {

inline constexpr std::size_t kWavefront = static_cast<std::size_t>(kTileSize) * kTileSize;

/// What shading reads of one sphere, side by side in one cache line: the gather loads a row as
/// two vectors of 8 fields and transposes 8 rows at a time (wavefront_passes.cpp).
struct alignas(64) SphereShading {
  float cx, cy, cz, radius;
  float ar, ag, ab;  // the attenuation: the albedo, 1 for a dielectric (as scatter() returns)
  float fuzz, ior;
  std::int32_t kind;  // MaterialKind
  std::int32_t unused[6] = {};
};
static_assert(sizeof(SphereShading) == 64);

/// SphereShading by sphere id, and one placeholder row past the spheres that misses read.
class ShadingTable {
 public:
  explicit ShadingTable(const Scene& scene);
  /// The row of sphere id: the placeholder for a miss.
  std::size_t index(std::uint32_t id) const {
    return id < rows_.size() - 1 ? id : rows_.size() - 1;
  }
  const SphereShading* rows() const { return rows_.data(); }

 private:
  std::vector<SphereShading> rows_;
};

// One cache line more than the lanes: with arrays 1 KiB apart, lane k of every fourth array lies
// a multiple of 4 KiB away, in the same set of the L1 cache, and a pass touches some 30 arrays.
template <class T>
using Lanes = std::array<T, kWavefront + 64 / sizeof(T)>;

/// A path's state between bounces, in 32 bytes: a path moves to another lane with one store of
/// its record, and the passes unpack eight records at a time into arrays by a transpose.
struct alignas(32) PathRecord {
  float tr, tg, tb;                         // throughput
  std::int32_t rays_left;                   // the rays the path may still trace, this one included
  std::uint32_t slot;                       // where the path's light goes (its radiance entry)
  std::uint32_t counter_low, counter_high;  // its PathRandom counter
  float sky;  // Sky::radiance's blend for the path's ray, 0.5 (normalize(dir).y + 1)

  std::uint64_t counter() const { return counter_low | std::uint64_t{counter_high} << 32; }
};
static_assert(sizeof(PathRecord) == 32);

/// A tile's paths: rays and hits for the kernel's stream call, and each path's record. The live
/// paths are packed at the front; the tracer fills the lanes behind them with new paths. Before
/// shading, the paths whose ray missed leave the lanes (their light is all they have left), so
/// that the passes, one array per quantity, run over the hits alone. 83 KiB: the tracer keeps
/// one per thread.
struct Wavefront {
  std::array<Ray, kWavefront> rays;  // the passes write origin to tmax: the masks stay as made
  std::array<Hit, kWavefront> hits;
  alignas(64) std::array<PathRecord, kWavefront> paths;
  std::size_t live = 0;
  // One bounce's misses' records: all that a miss needs for its light.
  alignas(64) std::array<PathRecord, kWavefront> missed;

  // One bounce's scratch, written and read by shade(); start() writes the new paths' state here
  // before it makes their records.
  alignas(64) Lanes<float> tr, tg, tb;  // throughput
  Lanes<std::uint64_t> counter;         // each path's PathRandom counter
  Lanes<std::int32_t> rays_left;        // the rays the path may still trace, this one included
  Lanes<std::uint32_t> slot;            // where the path's light goes (its radiance entry)
  alignas(64) Lanes<float> sky;         // the next ray's blend of Sky::radiance
  alignas(64) Lanes<float> ox, oy, oz, dx, dy, dz, t;  // the ray, then the next one
  alignas(64) Lanes<float> cx, cy, cz, radius, ar, ag, ab, fuzz, ior;
  alignas(64) Lanes<float> ex, ey, ez;  // surface()'s error bound
  alignas(64) Lanes<std::int32_t> kind, alive, row;
  alignas(64) Lanes<float> px, py, pz, nx, ny, nz;  // surface point and outward normal
  alignas(64) Lanes<float> onx, ony, onz;           // the normal against the incoming ray
  alignas(64) Lanes<float> ux, uy, uz;              // the unit incoming direction
  alignas(64) Lanes<float> eta, cosine, vx, vy, vz;
  alignas(64) Lanes<std::int32_t> reflects, redraw;
  Lanes<std::uint16_t> listed;           // the lanes draw() finishes one at a time
  alignas(64) Lanes<std::uint64_t> key;  // a new path's pixel index in the image
  Lanes<std::uint32_t> sample;           // and its sample
};

/// The first point (u, v) of the unit disk, u^2 + v^2 = s < 1, that PathRandom::unit_vector and
/// in_unit_disk accept drawing on from a path's counter, and the counter past it. The plain
/// rejection loop: drawing the first two candidates ahead and selecting, without the loop's
/// branch, measured no faster (docs/history.md, "Also tried, and the steps before the rounds").
struct DiskPoint {
  float u, v, s;
  std::uint64_t counter;
};

inline DiskPoint disk_point(std::uint64_t counter) {
  DiskPoint p{0.0f, 0.0f, 1.0f, counter};
  while (!(p.s < 1.0f)) {
    p.u = 2.0f * PathRandom::at(p.counter += PathRandom::kStep) - 1.0f;
    p.v = 2.0f * PathRandom::at(p.counter += PathRandom::kStep) - 1.0f;
    p.s = p.u * p.u + p.v * p.v;
  }
  return p;
}

/// Shades the hits of the wavefront's live paths: a path whose ray missed sets radiance[slot]
/// to 0 + its sky light (the sum of the path's light: its entry is 0 from the path's start, and
/// the path ends here); a hit scatters by its sphere's material and, unless absorbed or out of
/// rays (rays_left 1), stays live with its next ray (spawned as sphray::spawn does), throughput
/// and one ray fewer left. Packs the live paths again, in the order they were.
using ShadeFunction = void (*)(Wavefront& w, const ShadingTable& table, const Sky& sky,
                               Vec3* radiance);

/// Starts the paths in lanes [begin, live): from each lane's key (pixel index), sample and
/// pixel corner (px, py), its PathRandom counter past the camera's draws and its camera ray,
/// as PathRandom(seed, key, sample) then camera.ray(x + uniform, y + uniform, in_unit_disk()
/// when the camera has defocus) make them, and its record, with the throughput, rays left and
/// entry (slot) the tracer set in the lanes. seed_hash is PathRandom::seed_hash(seed).
using StartFunction = void (*)(Wavefront& w, std::size_t begin, const Camera& camera,
                               std::uint64_t seed_hash);

// The passes compiled once per instruction set (render/CMakeLists.txt: wavefront_passes.cpp),
// with the same float operations in the same order: every copy gives the same bits. The
// renderer names no instruction set in its code; the build gives the vector width.
// A build defines only the copies it compiles (shade_clones() lists them).
namespace baseline {
void shade(Wavefront& w, const ShadingTable& table, const Sky& sky, Vec3* radiance);
void start(Wavefront& w, std::size_t begin, const Camera& camera, std::uint64_t seed_hash);
}  // namespace baseline
namespace sse4_2 {
void shade(Wavefront& w, const ShadingTable& table, const Sky& sky, Vec3* radiance);
void start(Wavefront& w, std::size_t begin, const Camera& camera, std::uint64_t seed_hash);
}  // namespace sse4_2
namespace avx2 {
void shade(Wavefront& w, const ShadingTable& table, const Sky& sky, Vec3* radiance);
void start(Wavefront& w, std::size_t begin, const Camera& camera, std::uint64_t seed_hash);
}  // namespace avx2
namespace avx512 {
void shade(Wavefront& w, const ShadingTable& table, const Sky& sky, Vec3* radiance);
void start(Wavefront& w, std::size_t begin, const Camera& camera, std::uint64_t seed_hash);
}  // namespace avx512

/// One copy of shade() and the instruction set it was compiled for (Isa::scalar: the baseline).
struct ShadeClone {
  Isa isa;
  ShadeFunction shade;
  StartFunction start;
};

/// The copies this build has, best first, the baseline last.
std::span<const ShadeClone> shade_clones();

/// The best copy that runs where the kernel's queries run on `active` (sphray::active_isa(),
/// which SPHRAY_ISA can force lower).
const ShadeClone& clone_for(Isa active);
inline ShadeFunction shade_for(Isa active) {
  return clone_for(active).shade;
}

}  // namespace sphray::render
