// The path tracer's wavefront: a tile's live paths as one array per quantity, and their shading
// in passes over those arrays. The surfaces and the next rays' origins come from the kernel's
// array calls (sphray::surfaces and sphray::offset_origins); the materials (scatter of
// material.hpp) and the random draws are the renderer's passes: plain loops without calls or
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

/// What shading reads of one sphere's material, side by side in half a cache line: the gather
/// loads a row as one vector of 8 fields and transposes 8 rows at a time (wavefront_passes.cpp).
/// Its centre and radius the kernel's surfaces() reads from the spheres themselves.
struct alignas(32) SphereShading {
  float ar, ag, ab;  // the attenuation: the albedo, 1 for a dielectric (as scatter() returns)
  float fuzz, ior;
  std::int32_t kind;  // MaterialKind
  std::int32_t unused[2] = {};
};
static_assert(sizeof(SphereShading) == 32);

/// SphereShading by sphere id, and one placeholder row past the spheres that misses read; and
/// the spheres, for the kernel's surfaces().
class ShadingTable {
 public:
  explicit ShadingTable(const Scene& scene);
  SphereView spheres() const { return spheres_; }
  /// The row of sphere id: the placeholder for a miss.
  std::size_t index(std::uint32_t id) const {
    return id < rows_.size() - 1 ? id : rows_.size() - 1;
  }
  const SphereShading* rows() const { return rows_.data(); }

 private:
  SphereView spheres_;
  std::vector<SphereShading> rows_;
};

// One cache line more than the lanes: with arrays 1 KiB apart, lane k of every fourth array lies
// a multiple of 4 KiB away, in the same set of the L1 cache, and a pass touches some 30 arrays.
template <class T>
using Lanes = std::array<T, kWavefront + 64 / sizeof(T)>;
// Whole cache lines: each array of a part starts one, as the part does (alignas(64)).
static_assert(sizeof(Lanes<float>) % 64 == 0 && sizeof(Lanes<std::uint64_t>) % 64 == 0 &&
              sizeof(Lanes<std::uint16_t>) % 64 == 0 && sizeof(Lanes<bool>) % 64 == 0);

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

// One bounce's lanes, and a start() call's: the parts of a Wavefront that its passes
// (wavefront_passes.cpp) compute in, one array per quantity, lane k of each one path's. shade()
// runs its passes in this order: partition (the misses out), light_misses, gather (the hits'
// rays, spheres and records unpacked), surfaces, draw, scatter_all, spawn and compact (the next
// rays and records packed). Each part says which passes write it and which read it. No part holds
// anything from one shade() or start() call to the next: the records and rays do.

/// A path's state, unpacked from its record: what goes with the path from bounce to bounce.
/// gather writes it from the records (all but sky); draw advances the counter past its draws;
/// scatter_all multiplies the throughput by the sphere's attenuation, counts the traced ray off
/// rays_left and writes the next ray's sky blend; compact packs it into the records again.
/// For new paths the tracer writes throughput, rays_left and slot, and start() the counter (past
/// the camera's draws) and sky, then packs the records.
struct alignas(64) PathLanes {
  Lanes<float> throughput_r, throughput_g, throughput_b;
  Lanes<std::uint64_t> counter;   // the path's PathRandom counter
  Lanes<std::int32_t> rays_left;  // the rays the path may still trace, this one included
  Lanes<std::uint32_t> slot;      // where the path's light goes (its radiance entry)
  Lanes<float> sky;               // the next ray's blend of Sky::radiance (PathRecord::sky)
};

/// The path's ray and its hit, then its next ray. gather writes the ray from the kernel's rays,
/// t and id from its hits; surfaces reads them; scatter_all overwrites the direction with the
/// next ray's, and spawn the origin (spawn()'s), which compact packs into the kernel's rays.
/// start() writes the new paths' camera rays here and packs them into the kernel's rays.
struct alignas(64) RayLanes {
  Lanes<float> origin_x, origin_y, origin_z;
  Lanes<float> dir_x, dir_y, dir_z;
  Lanes<float> t;           // the hit's distance along the ray
  Lanes<std::uint32_t> id;  // the hit sphere
};

/// The hit sphere's shading row (SphereShading), by lane. gather writes it: row from the hits,
/// the rest from the ShadingTable's rows. surfaces reads ior; draw kind and fuzz; scatter_all
/// kind, fuzz and attenuation.
struct alignas(64) SphereLanes {
  Lanes<float> attenuation_r, attenuation_g, attenuation_b;  // SphereShading's ar, ag, ab
  Lanes<float> fuzz, ior;
  Lanes<std::int32_t> kind;  // MaterialKind
  Lanes<std::int32_t> row;   // the ShadingTable's row: ShadingTable::index(hit.id)
};

/// What sphray::surface() gives for the hit: surfaces writes it (the kernel's surfaces()) and
/// reads it for ScatterLanes' facing and eta; spawn reads it to offset the next ray's origin
/// (the kernel's offset_origins()).
struct alignas(64) SurfaceLanes {
  Lanes<float> point_x, point_y, point_z;
  Lanes<float> normal_x, normal_y, normal_z;  // outward
  Lanes<bool> front_face;
  Lanes<float> error_x, error_y, error_z;  // the point's error bound
};

/// scatter()'s inputs and outcome. surfaces writes the facing normal, the incoming direction,
/// eta and cosine; draw writes drawn, redraw and reflects (a dielectric's draw); scatter_all
/// reads them all and writes alive, which compact reads.
struct alignas(64) ScatterLanes {
  Lanes<float> facing_x, facing_y, facing_z;        // the normal against the incoming ray
  Lanes<float> incoming_x, incoming_y, incoming_z;  // the incoming direction, of unit length
  Lanes<float> eta;     // a dielectric's ratio of indices, the ray's side over the other's
  Lanes<float> cosine;  // between facing and the reversed incoming direction, at most 1
  Lanes<float> drawn_x, drawn_y, drawn_z;  // the unit vector drawn (0 where none is drawn)
  Lanes<std::int32_t> reflects;            // a dielectric reflects rather than refracts
  Lanes<std::int32_t> redraw;  // draw() finishes the lane alone: a dielectric, or no point yet
                               // inside the disk of the points drawn ahead
  Lanes<std::int32_t> alive;   // the path goes on: not absorbed, and rays left
};

/// The new paths' camera samples, lanes [begin, live) of a start() call. The tracer writes
/// pixel, sample and the pixel's corner (x, y); start() moves x, y to the sample's point in the
/// pixel, draws the lens point and redraw, and reads them all for the camera rays. Nothing
/// reads them once start() returns.
struct alignas(64) CameraLanes {
  Lanes<std::uint64_t> pixel;   // the pixel's index in the image (PathRandom's key)
  Lanes<std::uint32_t> sample;  // the path's sample of its pixel
  Lanes<float> x, y;            // the image point: the pixel's corner, then the sample's point
  Lanes<float> lens_x, lens_y;  // the lens point in the unit disk (unread without defocus)
  Lanes<std::int32_t> redraw;   // the lens points drawn ahead all rejected: redraw_lens draws on
};

/// A tile's paths, one per lane: rays and hits for the kernel's stream call, each path's record,
/// and the lanes the passes compute in. 85 KiB: the tracer keeps one per thread.
///
/// The lanes, for every array here: lane k holds the path in lane k. The live paths are lanes
/// [0, live), packed at the front in the order they started; the tracer fills the lanes behind
/// them with new paths. Before shading, the paths whose ray missed leave the lanes (their light
/// is all they have left), so that the passes run over the hits alone. The passes compute the
/// lanes past the live ones up to the next multiple of 16 (wavefront_passes.cpp, padded()):
/// those hold stale values of earlier rounds, never undefined ones (the tracer's wavefront is
/// zeroed once, when made), and what is computed or stored in them is never read as a live
/// path's, nor reaches a radiance entry.
struct Wavefront {
  // The kernel's queue. The stream call reads rays [0, live) and writes their hits; shade()
  // reads both and leaves in rays the next rays of the paths still live, start() the new
  // paths' camera rays (the passes write origin to tmax: the masks stay as made).
  std::array<Ray, kWavefront> rays;
  std::array<Hit, kWavefront> hits;
  std::size_t live = 0;

  // The records. paths: the live paths' state between bounces, which partition moves with
  // their rays and hits, gather unpacks, and compact and start() write. missed: one bounce's
  // misses, all that a miss needs for its light; partition writes them, light_misses reads.
  alignas(64) std::array<PathRecord, kWavefront> paths;
  alignas(64) std::array<PathRecord, kWavefront> missed;

  // One bounce's lanes, shade()'s.
  PathLanes path;
  RayLanes ray;
  SphereLanes sphere;
  SurfaceLanes surface;
  ScatterLanes scatter;
  // The lanes a pass finishes one at a time (list_redraws), in order: draw()'s (the redraw
  // flags of scatter) or start()'s (those of camera), written and read within that pass.
  Lanes<std::uint16_t> listed;

  // A start() call's lanes.
  CameraLanes camera;
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

/// Starts the paths in lanes [begin, live): from each lane's camera sample (pixel index, sample
/// and pixel corner x, y), its PathRandom counter past the camera's draws and its camera ray, as
/// PathRandom(seed, pixel, sample) then camera.ray(x + uniform, y + uniform, in_unit_disk()
/// when the camera has defocus) make them, and its record, with the throughput, rays left and
/// entry (slot) the tracer set in its path lanes. seed_hash is PathRandom::seed_hash(seed).
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
