// The wavefront's shading passes. render/CMakeLists.txt compiles this file once per instruction
// set, each copy in its own namespace (SPHRAY_SHADE_ISA); wavefront.cpp picks one at run time.
// Only the vector width differs between the copies: no FMA contraction (-ffp-contract=off) and
// the same operations in the same order, so every copy gives the same bits
// (tests/render/wavefront_test.cpp runs each one).
#include "path/wavefront.hpp"

#include "sphray/render/camera.hpp"

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>

namespace sphray::render::SPHRAY_SHADE_ISA {
namespace {

constexpr auto kLambertian = static_cast<std::int32_t>(MaterialKind::lambertian);
constexpr auto kMetal = static_cast<std::int32_t>(MaterialKind::metal);
constexpr auto kDielectric = static_cast<std::int32_t>(MaterialKind::dielectric);

// Sky::radiance's blend for a ray's direction, 0.5 (normalize(dir).y + 1): computed with the ray,
// in a vector pass, and kept in its path's record, it is all a miss needs besides the throughput.
float sky_blend(float dx, float dy, float dz) {
  const float length = std::sqrt(dx * dx + dy * dy + dz * dz);
  return 0.5f * (dy / length + 1.0f);
}

// The lanes a float pass runs over: the live ones and those up to the next multiple of 16, the
// widest copy's vector, so that no pass ends in a tail of lanes one at a time (GCC's epilogue:
// scalar divisions and square roots, a visible share of shade()'s profile; docs/history.md,
// "The third round: misses out before shading"). What the lanes past the live ones hold, and
// what becomes of what is computed in them: Wavefront's lane rules (wavefront.hpp).
constexpr std::size_t kLaneBlock = 16;
static_assert(kWavefront % kLaneBlock == 0);
std::size_t padded(std::size_t live) {
  return (live + kLaneBlock - 1) / kLaneBlock * kLaneBlock;
}

// Eight floats (or their bits), moved between layouts by shuffles of GCC's vector extensions:
// the build's flags pick the instructions. Moves only: every copy gives the same bits. Only the
// copies the build says transpose do (SPHRAY_SHADE_TRANSPOSES, render/CMakeLists.txt); the
// others move one lane at a time, faster for them.
constexpr bool kTransposes = SPHRAY_SHADE_TRANSPOSES != 0;
// The points of the disk draw() and start() draw for every lane in their vector loops (1 or 2,
// render/CMakeLists.txt): two where the vectors have a 64-bit lane multiply (SplitMix64's), one
// where it is emulated and the second point costs more than the lanes that go on one at a time.
constexpr std::uint64_t kPointsAhead = SPHRAY_SHADE_POINTS_AHEAD;
using Floats8 = float __attribute__((vector_size(32)));
static_assert(sizeof(Floats8) == 8 * sizeof(float));

// Vectors by reference only: passing one by value would depend on the instruction set's ABI.
void load8(Floats8& v, const void* from) {
  std::memcpy(&v, from, sizeof v);
}
void store8(void* to, const Floats8& v) {
  std::memcpy(to, &v, sizeof v);
}

// Eight vectors transposed in place: v[i][j] becomes v[j][i]. Inline, or the vectors go through
// memory.
[[gnu::always_inline]] inline void transpose8(Floats8 (&v)[8]) {
  Floats8 t[8], s[8];
  for (int i = 0; i < 8; i += 2) {  // pairs of rows interleaved
    t[i] = __builtin_shufflevector(v[i], v[i + 1], 0, 8, 1, 9, 4, 12, 5, 13);
    t[i + 1] = __builtin_shufflevector(v[i], v[i + 1], 2, 10, 3, 11, 6, 14, 7, 15);
  }
  for (int i = 0; i < 8; i += 4) {  // then pairs of those pairs
    s[i] = __builtin_shufflevector(t[i], t[i + 2], 0, 1, 8, 9, 4, 5, 12, 13);
    s[i + 1] = __builtin_shufflevector(t[i], t[i + 2], 2, 3, 10, 11, 6, 7, 14, 15);
    s[i + 2] = __builtin_shufflevector(t[i + 1], t[i + 3], 0, 1, 8, 9, 4, 5, 12, 13);
    s[i + 3] = __builtin_shufflevector(t[i + 1], t[i + 3], 2, 3, 10, 11, 6, 7, 14, 15);
  }
  for (int i = 0; i < 4; ++i) {  // then the halves of four rows
    v[i] = __builtin_shufflevector(s[i], s[i + 4], 0, 1, 2, 3, 8, 9, 10, 11);
    v[i + 4] = __builtin_shufflevector(s[i], s[i + 4], 4, 5, 6, 7, 12, 13, 14, 15);
  }
}

// A PathRecord's eight fields, in the order the record transposes put them.
static_assert(offsetof(PathRecord, tr) == 0 && offsetof(PathRecord, rays_left) == 12 &&
              offsetof(PathRecord, slot) == 16 && offsetof(PathRecord, counter_low) == 20 &&
              offsetof(PathRecord, counter_high) == 24 && offsetof(PathRecord, sky) == 28);

// A Ray's first eight floats: origin, direction, tmin and tmax.
static_assert(offsetof(Ray, origin) == 0 && offsetof(Ray, dir) == 12 && offsetof(Ray, tmax) == 28);

// Each live path's sphere: its row's fields, one array per quantity. Eight lanes at a time,
// their rows loaded whole and transposed: a loop of one load a field costs some 30 instructions
// a lane (GCC's tuning here emits no gather instructions). The last lanes one by one.
void gather_rows(Wavefront& w, const SphereShading* __restrict rows, std::size_t lanes) {
  SphereLanes& sphere = w.sphere;
  std::size_t k = 0;
  for (; kTransposes && k + 8 <= lanes; k += 8) {
    Floats8 v[8];
    for (int i = 0; i < 8; ++i)
      load8(v[i], &rows[sphere.row[k + i]]);
    transpose8(v);
    store8(&sphere.attenuation_r[k], v[0]);
    store8(&sphere.attenuation_g[k], v[1]);
    store8(&sphere.attenuation_b[k], v[2]);
    store8(&sphere.fuzz[k], v[3]), store8(&sphere.ior[k], v[4]), store8(&sphere.kind[k], v[5]);
  }
  for (; k < lanes; ++k) {
    const SphereShading& s = rows[sphere.row[k]];
    sphere.attenuation_r[k] = s.ar, sphere.attenuation_g[k] = s.ag, sphere.attenuation_b[k] = s.ab;
    sphere.fuzz[k] = s.fuzz, sphere.ior[k] = s.ior, sphere.kind[k] = s.kind;
  }
}

// The records of lanes [0, lanes) as one array per quantity, eight at a time transposed (the
// last eight may pass the live lanes: every lane has a record), or one lane at a time. All but
// the sky blend, which scatter_all writes for the next ray.
void unpack_records(Wavefront& w, std::size_t lanes) {
  static_assert(kWavefront % 8 == 0);
  PathLanes& path = w.path;
  std::size_t k = 0;
  for (; kTransposes && k < lanes; k += 8) {
    Floats8 v[8];
    for (std::size_t i = 0; i < 8; ++i)
      load8(v[i], &w.paths[k + i]);
    transpose8(v);
    store8(&path.throughput_r[k], v[0]);
    store8(&path.throughput_g[k], v[1]);
    store8(&path.throughput_b[k], v[2]);
    store8(&path.rays_left[k], v[3]), store8(&path.slot[k], v[4]);
    const Floats8 c0 = __builtin_shufflevector(v[5], v[6], 0, 8, 1, 9, 2, 10, 3, 11);
    const Floats8 c1 = __builtin_shufflevector(v[5], v[6], 4, 12, 5, 13, 6, 14, 7, 15);
    store8(&path.counter[k], c0), store8(&path.counter[k + 4], c1);
  }
  for (; k < lanes; ++k) {
    const PathRecord& record = w.paths[k];
    path.throughput_r[k] = record.tr, path.throughput_g[k] = record.tg;
    path.throughput_b[k] = record.tb;
    path.rays_left[k] = record.rays_left, path.slot[k] = record.slot;
    path.counter[k] = record.counter();
  }
}

// Each hit path's ray (eight at a time transposed, the last ones one by one), hit, sphere and
// state, one array per quantity: the ray lanes, the sphere lanes and the path lanes.
void gather(Wavefront& w, const ShadingTable& table, std::size_t lanes) {
  RayLanes& ray = w.ray;
  std::size_t k = 0;
  for (; kTransposes && k + 8 <= lanes; k += 8) {
    Floats8 v[8];
    for (int i = 0; i < 8; ++i)
      load8(v[i], &w.rays[k + i]);
    transpose8(v);
    store8(&ray.origin_x[k], v[0]), store8(&ray.origin_y[k], v[1]);
    store8(&ray.origin_z[k], v[2]);
    store8(&ray.dir_x[k], v[3]), store8(&ray.dir_y[k], v[4]), store8(&ray.dir_z[k], v[5]);
  }
  for (; k < lanes; ++k) {
    const Ray& kernel_ray = w.rays[k];
    ray.origin_x[k] = kernel_ray.origin.x, ray.origin_y[k] = kernel_ray.origin.y;
    ray.origin_z[k] = kernel_ray.origin.z;
    ray.dir_x[k] = kernel_ray.dir.x, ray.dir_y[k] = kernel_ray.dir.y;
    ray.dir_z[k] = kernel_ray.dir.z;
  }
  for (k = 0; k < lanes; ++k) {
    ray.t[k] = w.hits[k].t;
    ray.id[k] = w.hits[k].id;
    w.sphere.row[k] = static_cast<std::int32_t>(table.index(w.hits[k].id));
  }
  gather_rows(w, table.rows(), lanes);
  unpack_records(w, lanes);
}

// The surface lanes as the kernel's arrays.
SurfaceArrays surface_arrays(SurfaceLanes& s, std::size_t lanes) {
  return {s.point_x.data(),
          s.point_y.data(),
          s.point_z.data(),
          s.normal_x.data(),
          s.normal_y.data(),
          s.normal_z.data(),
          s.front_face.data(),
          s.error_x.data(),
          s.error_y.data(),
          s.error_z.data(),
          lanes};
}

// sphray::surface() for every lane (the kernel's surfaces()), then the unit incoming direction
// and the normal against it.
void surfaces(Wavefront& w, const SphereView spheres, std::size_t lanes) {
  RayLanes& ray = w.ray;  // only read: HitArrays' pointers are mutable
  const SurfaceLanes& surface = w.surface;
  const RayArrays rays{ray.origin_x.data(),
                       ray.origin_y.data(),
                       ray.origin_z.data(),
                       ray.dir_x.data(),
                       ray.dir_y.data(),
                       ray.dir_z.data(),
                       nullptr,
                       nullptr,
                       nullptr,
                       lanes};  // tmin 0, as the kernel's rays have it
  const HitArrays hits{ray.t.data(), ray.id.data(), lanes};
  sphray::surfaces(spheres, rays, hits, surface_arrays(w.surface, lanes));
  const SphereLanes& sphere = w.sphere;
  ScatterLanes& scatter = w.scatter;
  // The front faces as bytes (a bool's object representation): GCC vectorises no load of bool.
  const auto* front_faces = reinterpret_cast<const unsigned char*>(surface.front_face.data());
  for (std::size_t k = 0; k < lanes; ++k) {
    const float dx = ray.dir_x[k], dy = ray.dir_y[k], dz = ray.dir_z[k];
    const float length = std::sqrt(dx * dx + dy * dy + dz * dz);
    scatter.incoming_x[k] = dx / length, scatter.incoming_y[k] = dy / length;
    scatter.incoming_z[k] = dz / length;
    // The normal against the incoming ray (as scatter() turns it), and a dielectric's eta.
    // Every load and store unconditional: a conditional one keeps GCC from vectorising.
    const bool front = front_faces[k] != 0;
    const float nx = surface.normal_x[k], ny = surface.normal_y[k], nz = surface.normal_z[k];
    const float ox = front ? nx : -nx, oy = front ? ny : -ny, oz = front ? nz : -nz;
    scatter.facing_x[k] = ox, scatter.facing_y[k] = oy, scatter.facing_z[k] = oz;
    const float ior = sphere.ior[k], inverse = 1.0f / ior;
    scatter.eta[k] = front ? inverse : ior;
    const float c =
        -scatter.incoming_x[k] * ox + -scatter.incoming_y[k] * oy + -scatter.incoming_z[k] * oz;
    scatter.cosine[k] = 1.0f < c ? 1.0f : c;
  }
}

// Lists in w.listed the lanes of [begin, end) whose flag in redraw (a pass's own: the scatter
// lanes' or the camera lanes') is set, in order, and returns how many: the flags of 64 lanes as
// the bits of a word (a loop that vectorises), then the word's set bits. (A loop adding each
// flag to the count after storing its lane, a store and a dependent add every lane, was a
// visible share of shade()'s profile; docs/history.md, "The third round: misses out before
// shading".)
std::size_t list_redraws(Wavefront& w, const Lanes<std::int32_t>& redraw, std::size_t begin,
                         std::size_t end) {
  static_assert(kWavefront % 64 == 0);
  constexpr std::uint64_t kAll = ~std::uint64_t{0};
  std::size_t count = 0;
  for (std::size_t base = begin / 64 * 64; base < end; base += 64) {
    std::uint64_t bits = 0;
    for (std::size_t i = 0; i < 64; ++i)
      bits |= static_cast<std::uint64_t>(redraw[base + i] & 1) << i;
    bits &= base < begin ? kAll << (begin - base) : kAll;
    bits &= end - base < 64 ? (std::uint64_t{1} << (end - base)) - 1 : kAll;
    for (; bits != 0; bits &= bits - 1)
      w.listed[count++] = static_cast<std::uint16_t>(base + std::countr_zero(bits));
  }
  return count;
}

// A dielectric's choice between reflection and refraction, drawn only where it may refract
// (scatter()'s dielectric: a matched index is no interface, and takes no draw).
void choose_reflection(Wavefront& w, std::size_t k) {
  const float cosine = w.scatter.cosine[k], eta = w.scatter.eta[k];
  const float sine = std::sqrt(0.0f < 1.0f - cosine * cosine ? 1.0f - cosine * cosine : 0.0f);
  const bool cannot_refract = eta * sine > 1.0f;
  if (cannot_refract || eta == 1.0f) {
    w.scatter.reflects[k] = cannot_refract;
    return;
  }
  w.path.counter[k] += PathRandom::kStep;
  w.scatter.reflects[k] = schlick(cosine, eta) > PathRandom::at(w.path.counter[k]);
}

// PathRandom::at, with the top 24 bits converted through int32 (exact either way): the
// conversion from 64-bit integers has no vector form before AVX-512.
float uniform_at(std::uint64_t counter) {
  return static_cast<float>(static_cast<std::int32_t>(PathRandom::mix(counter) >> 40)) * 0x1p-24f;
}

// Each path's draws, in the order scatter() makes them: a Lambertian and a fuzzed metal draw a
// unit vector, a dielectric that may refract a uniform. First every lane's first two points of
// the disk, in one loop that vectorises (the first inside kept where a unit vector was wanted:
// one of them is for 95% of the lanes, the first alone for pi/4); then, one lane at a time, the
// rest: the next tries past two rejected points, and the dielectrics. (The same draws before,
// with one branch per material, cost more: the draws then ran one lane at a time. With one point
// ahead rather than two, a lane in five went on one lane at a time.)
void draw(Wavefront& w, std::size_t hits, std::size_t lanes) {
  constexpr std::uint64_t kStep = PathRandom::kStep;
  const SphereLanes& sphere = w.sphere;
  PathLanes& path = w.path;
  ScatterLanes& scatter = w.scatter;
  for (std::size_t k = 0; k < lanes; ++k) {
    const std::uint64_t counter = path.counter[k];
    const float u1 = 2.0f * uniform_at(counter + kStep) - 1.0f;
    const float v1 = 2.0f * uniform_at(counter + 2 * kStep) - 1.0f;
    const float s1 = u1 * u1 + v1 * v1;
    // With one point ahead the second is the first again: never taken.
    const float u2 = kPointsAhead > 1 ? 2.0f * uniform_at(counter + 3 * kStep) - 1.0f : u1;
    const float v2 = kPointsAhead > 1 ? 2.0f * uniform_at(counter + 4 * kStep) - 1.0f : v1;
    const float s2 = u2 * u2 + v2 * v2;
    const std::int32_t kind = sphere.kind[k];
    const std::int32_t fuzzed = (kind == kMetal ? 1 : 0) & (sphere.fuzz[k] > 0.0f ? 1 : 0);
    const std::int32_t wants = (kind == kLambertian ? 1 : 0) | fuzzed;
    const std::int32_t first = s1 < 1.0f ? 1 : 0;
    const std::int32_t second = (1 - first) & (s2 < 1.0f ? 1 : 0);
    const std::int32_t drawn = wants & (first | second);
    const float u = first ? u1 : u2, v = first ? v1 : v2, s = first ? s1 : s2;
    const float scale = 2.0f * std::sqrt(1.0f - s);
    scatter.drawn_x[k] = drawn ? u * scale : 0.0f;
    scatter.drawn_y[k] = drawn ? v * scale : 0.0f;
    scatter.drawn_z[k] = drawn ? 1.0f - 2.0f * s : 0.0f;
    const std::uint64_t past = first ? counter + 2 * kStep : counter + 4 * kStep;
    path.counter[k] = drawn ? past : counter;
    scatter.reflects[k] = 0;
    scatter.redraw[k] = (wants & (1 - (first | second))) | (kind == kDielectric ? 1 : 0);
  }
  const std::size_t count = list_redraws(w, scatter.redraw, 0, hits);
  for (std::size_t j = 0; j < count; ++j) {
    const std::size_t k = w.listed[j];
    if (sphere.kind[k] == kDielectric) {
      choose_reflection(w, k);
      continue;
    }
    const DiskPoint p = disk_point(path.counter[k] + 2 * kPointsAhead * kStep);  // past them
    const float scale = 2.0f * std::sqrt(1.0f - p.s);
    scatter.drawn_x[k] = p.u * scale, scatter.drawn_y[k] = p.v * scale;
    scatter.drawn_z[k] = 1.0f - 2.0f * p.s;
    path.counter[k] = p.counter;
  }
}

// spawn()'s origin of every lane's next ray: the kernel's offset_origins() from the surface
// along the next direction.
void spawn(Wavefront& w, std::size_t lanes) {
  RayLanes& ray = w.ray;
  sphray::offset_origins(surface_arrays(w.surface, lanes),
                         {ray.dir_x.data(), ray.dir_y.data(), ray.dir_z.data(), lanes},
                         {ray.origin_x.data(), ray.origin_y.data(), ray.origin_z.data(), lanes});
}

// scatter()'s direction and attenuation for every lane, the three materials computed and one
// selected.
void scatter_all(Wavefront& w, std::size_t lanes) {
  const SphereLanes& sphere = w.sphere;
  PathLanes& path = w.path;
  RayLanes& ray = w.ray;
  ScatterLanes& scatter = w.scatter;
  for (std::size_t k = 0; k < lanes; ++k) {
    const float nx = scatter.facing_x[k], ny = scatter.facing_y[k], nz = scatter.facing_z[k];
    const float ux = scatter.incoming_x[k], uy = scatter.incoming_y[k], uz = scatter.incoming_z[k];
    const float vx = scatter.drawn_x[k], vy = scatter.drawn_y[k], vz = scatter.drawn_z[k];
    // Lambertian: n + a unit vector, n itself where they nearly cancel.
    const float lx = nx + vx, ly = ny + vy, lz = nz + vz;
    // near_zero() as a sum of floats: GCC vectorises no && of float comparisons.
    const float far_x = std::fabs(lx) < 1e-8f ? 0.0f : 1.0f;
    const float far_y = std::fabs(ly) < 1e-8f ? 0.0f : 1.0f;
    const float far_z = std::fabs(lz) < 1e-8f ? 0.0f : 1.0f;
    const bool near_zero = far_x + far_y + far_z == 0.0f;
    // Metal: the mirror direction, fuzzed; absorbed if that goes below the surface.
    const float twice = 2.0f * (ux * nx + uy * ny + uz * nz);
    const float rx = ux - twice * nx, ry = uy - twice * ny, rz = uz - twice * nz;
    const float rlength = std::sqrt(rx * rx + ry * ry + rz * rz);
    const float fuzz = sphere.fuzz[k];
    const bool fuzzed = fuzz > 0.0f;
    const float mx = fuzzed ? rx / rlength + fuzz * vx : rx;
    const float my = fuzzed ? ry / rlength + fuzz * vy : ry;
    const float mz = fuzzed ? rz / rlength + fuzz * vz : rz;
    // Integers of one width, no bool: GCC vectorises no mix of them.
    const std::int32_t below = mx * nx + my * ny + mz * nz <= 0.0f ? 1 : 0;
    const std::int32_t absorbed = (sphere.kind[k] == kMetal ? 1 : 0) & below;
    // Dielectric: the mirror direction or refract()'s.
    const float eta = scatter.eta[k], cosine = scatter.cosine[k];
    const float ax = eta * (ux + cosine * nx), ay = eta * (uy + cosine * ny),
                az = eta * (uz + cosine * nz);
    const float along = -std::sqrt(std::fabs(1.0f - (ax * ax + ay * ay + az * az)));
    const bool reflects = scatter.reflects[k];
    const float gx = reflects ? rx : ax + along * nx;
    const float gy = reflects ? ry : ay + along * ny;
    const float gz = reflects ? rz : az + along * nz;
    const std::int32_t kind = sphere.kind[k];
    const float dx = kind == kLambertian ? (near_zero ? nx : lx) : (kind == kMetal ? mx : gx);
    const float dy = kind == kLambertian ? (near_zero ? ny : ly) : (kind == kMetal ? my : gy);
    const float dz = kind == kLambertian ? (near_zero ? nz : lz) : (kind == kMetal ? mz : gz);
    ray.dir_x[k] = dx, ray.dir_y[k] = dy, ray.dir_z[k] = dz;
    path.sky[k] = sky_blend(dx, dy, dz);
    // A path that traced its last ray brings no light, as the book's max_depth.
    const std::int32_t more = path.rays_left[k] > 1 ? 1 : 0;
    scatter.alive[k] = (1 - absorbed) & more;
    path.rays_left[k] = path.rays_left[k] - 1;
    path.throughput_r[k] = path.throughput_r[k] * sphere.attenuation_r[k];
    path.throughput_g[k] = path.throughput_g[k] * sphere.attenuation_g[k];
    path.throughput_b[k] = path.throughput_b[k] * sphere.attenuation_b[k];
  }
}

// Lanes k to k + 8's next rays as the kernel's Rays' first 8 floats (the mask stays as the Ray
// was made), by a transpose: row i is lane k + i's ray.
[[gnu::always_inline]] inline void next_rays(const RayLanes& ray, std::size_t k,
                                             Floats8 (&rays)[8]) {
  load8(rays[0], &ray.origin_x[k]), load8(rays[1], &ray.origin_y[k]);
  load8(rays[2], &ray.origin_z[k]);
  load8(rays[3], &ray.dir_x[k]), load8(rays[4], &ray.dir_y[k]), load8(rays[5], &ray.dir_z[k]);
  const Ray unbounded{};  // tmin and tmax as every Ray has them
  rays[6] = Floats8{} + unbounded.tmin;
  rays[7] = Floats8{} + unbounded.tmax;
  transpose8(rays);
}

// Lanes k to k + 8's state that goes with a path to its next lane, as records (the bits of the
// throughput, rays left, entry, the counter's low and high halves and the sky blend, in
// PathRecord's order), by a transpose: row i is lane k + i's record.
[[gnu::always_inline]] inline void path_records(const PathLanes& path, std::size_t k,
                                                Floats8 (&v)[8]) {
  Floats8 c0, c1;
  load8(v[0], &path.throughput_r[k]), load8(v[1], &path.throughput_g[k]);
  load8(v[2], &path.throughput_b[k]);
  load8(v[3], &path.rays_left[k]), load8(v[4], &path.slot[k]);
  load8(c0, &path.counter[k]), load8(c1, &path.counter[k + 4]);
  v[5] = __builtin_shufflevector(c0, c1, 0, 2, 4, 6, 8, 10, 12, 14);
  v[6] = __builtin_shufflevector(c0, c1, 1, 3, 5, 7, 9, 11, 13, 15);
  load8(v[7], &path.sky[k]);
  transpose8(v);
}

// Lane k's record, as path_records() makes them.
PathRecord record_of(const PathLanes& path, std::size_t k) {
  const std::uint64_t counter = path.counter[k];
  return {path.throughput_r[k],
          path.throughput_g[k],
          path.throughput_b[k],
          path.rays_left[k],
          path.slot[k],
          static_cast<std::uint32_t>(counter),
          static_cast<std::uint32_t>(counter >> 32),
          path.sky[k]};
}
// The paths whose ray hit move to the front of the lanes, in order (ray, hit and record); the
// others' records go to the misses' array. Each record is stored to both places and kept in one:
// no branch. Returns the hits.
std::size_t partition(Wavefront& w, std::size_t live) {
  std::size_t hits = 0, misses = 0;
  for (std::size_t k = 0; k < live; ++k) {
    Floats8 ray, path;
    load8(ray, &w.rays[k]), load8(path, &w.paths[k]);
    const Hit hit = w.hits[k];
    store8(&w.rays[hits], ray), store8(&w.paths[hits], path);
    w.hits[hits] = hit;
    store8(&w.missed[misses], path);
    const std::size_t found = hit.found() ? 1 : 0;
    hits += found, misses += 1 - found;
  }
  return hits;
}

// Each miss's light, its throughput times Sky::radiance(dir), to its entry: 0 + the light, the
// sum the entry (0 since the path started) makes with it, without reading the entry.
void light_misses(const Wavefront& w, const Sky& sky, std::size_t misses, Vec3* radiance) {
  const Vec3 horizon = sky.horizon, zenith = sky.zenith;
  for (std::size_t j = 0; j < misses; ++j) {
    const PathRecord& path = w.missed[j];
    const float a = path.sky;
    const float lr = path.tr * ((1.0f - a) * horizon.x + a * zenith.x);
    const float lg = path.tg * ((1.0f - a) * horizon.y + a * zenith.y);
    const float lb = path.tb * ((1.0f - a) * horizon.z + a * zenith.z);
    radiance[path.slot] = Vec3{0.0f + lr, 0.0f + lg, 0.0f + lb};
  }
}

// The paths still going move to the front, their next rays into the kernel's array and their
// state into records. Written for every lane, kept only for the live ones: no branch. Eight
// lanes at a time, their rays and records made by transposes, each one store (moved one float
// at a time, a lane took some 30 instructions); of the last eight, those up to hits. Returns
// the paths kept.
std::size_t compact(Wavefront& w, std::size_t hits) {
  const RayLanes& ray = w.ray;
  std::size_t k = 0, kept = 0;
  for (; kTransposes && k < hits; k += 8) {
    Floats8 rays[8], records[8];
    next_rays(ray, k, rays);
    path_records(w.path, k, records);
    const std::size_t lanes = hits - k < 8 ? hits - k : 8;
    for (std::size_t i = 0; i < lanes; ++i) {
      store8(&w.rays[kept], rays[i]);
      store8(&w.paths[kept], records[i]);
      kept += static_cast<std::size_t>(w.scatter.alive[k + i]);
    }
  }
  for (; k < hits; ++k) {
    w.rays[kept] = Ray{{ray.origin_x[k], ray.origin_y[k], ray.origin_z[k]},
                       {ray.dir_x[k], ray.dir_y[k], ray.dir_z[k]}};
    w.paths[kept] = record_of(w.path, k);
    kept += static_cast<std::size_t>(w.scatter.alive[k]);
  }
  return kept;
}

// A camera with a lens: the first kPointsAhead points of its disk for the new paths in lanes
// [begin, live) (as in draw()), from their counters past the point in the pixel.
void draw_lens(Wavefront& w, std::size_t begin, std::size_t live) {
  constexpr std::uint64_t kStep = PathRandom::kStep;
  for (std::size_t k = begin; k < live; ++k) {
    const std::uint64_t counter = w.path.counter[k];
    const float u1 = 2.0f * uniform_at(counter + kStep) - 1.0f;
    const float v1 = 2.0f * uniform_at(counter + 2 * kStep) - 1.0f;
    const float u2 = kPointsAhead > 1 ? 2.0f * uniform_at(counter + 3 * kStep) - 1.0f : u1;
    const float v2 = kPointsAhead > 1 ? 2.0f * uniform_at(counter + 4 * kStep) - 1.0f : v1;
    const std::int32_t first = u1 * u1 + v1 * v1 < 1.0f ? 1 : 0;
    const std::int32_t second = u2 * u2 + v2 * v2 < 1.0f ? 1 : 0;
    w.camera.lens_x[k] = first ? u1 : u2, w.camera.lens_y[k] = first ? v1 : v2;
    w.camera.redraw[k] = (1 - first) & (1 - second);
    // Past the second point, if drawn, where the first was rejected: a lane with every point
    // rejected goes on from its counter in redraw_lens.
    w.path.counter[k] = counter + (first ? 2 * kStep : 2 * kPointsAhead * kStep);
  }
}

// The rejected lens points' next tries, one lane at a time: their draws go on past the points
// start() drew (the path's fourth draw, or sixth with two points ahead).
void redraw_lens(Wavefront& w, std::size_t begin) {
  const std::size_t count = list_redraws(w, w.camera.redraw, begin, w.live);
  for (std::size_t j = 0; j < count; ++j) {
    const std::size_t k = w.listed[j];
    const DiskPoint p = disk_point(w.path.counter[k]);
    w.camera.lens_x[k] = p.u, w.camera.lens_y[k] = p.v;
    w.path.counter[k] = p.counter;
  }
}

}  // namespace

void start(Wavefront& w, std::size_t begin, const Camera& camera, std::uint64_t seed_hash) {
  constexpr std::uint64_t kStep = PathRandom::kStep;
  const std::size_t live = w.live;  // a copy: the counters' stores could alias it, as integers
  const bool lens = camera.has_defocus();
  // The path's random stream (PathRandom's constructor, its seed's mix given) and the point in
  // the pixel; the counter past them.
  for (std::size_t k = begin; k < live; ++k) {
    const std::uint64_t counter = PathRandom::mix(PathRandom::mix(seed_hash ^ w.camera.pixel[k]) ^
                                                  (std::uint64_t{w.camera.sample[k]} << 32));
    w.camera.x[k] = w.camera.x[k] + uniform_at(counter + kStep);
    w.camera.y[k] = w.camera.y[k] + uniform_at(counter + 2 * kStep);
    w.path.counter[k] = counter + 2 * kStep;
  }
  if (lens) {  // a pinhole draws no lens point, and its rays read none
    draw_lens(w, begin, live);
    redraw_lens(w, begin);
  }
  const Camera copy = camera;  // a local: no store to the lanes can change it
  RayLanes& ray = w.ray;
  // The camera rays as lanes, and their sky blend: a loop per kind of camera, without the
  // lens's branch, which GCC vectorises.
  const auto set_ray = [&w, &ray](std::size_t k, const Ray& r) {
    ray.origin_x[k] = r.origin.x, ray.origin_y[k] = r.origin.y, ray.origin_z[k] = r.origin.z;
    ray.dir_x[k] = r.dir.x, ray.dir_y[k] = r.dir.y, ray.dir_z[k] = r.dir.z;
    w.path.sky[k] = sky_blend(r.dir.x, r.dir.y, r.dir.z);
  };
  if (lens) {
    for (std::size_t k = begin; k < live; ++k)
      set_ray(k,
              copy.lens_ray(w.camera.x[k], w.camera.y[k], w.camera.lens_x[k], w.camera.lens_y[k]));
  } else {
    for (std::size_t k = begin; k < live; ++k)
      set_ray(k, copy.ray(w.camera.x[k], w.camera.y[k]));
  }
  // The new paths' rays and records: eight at a time transposed, or one by one. All eight rows
  // stored where the arrays have them (the lanes past live are free): a count of rows made GCC
  // copy them with a string instruction, a large share of start() (docs/history.md, "The third
  // round: misses out before shading").
  std::size_t k = begin;
  for (; kTransposes && k + 8 <= kWavefront && k < live; k += 8) {
    Floats8 rays[8], records[8];
    next_rays(ray, k, rays);
    path_records(w.path, k, records);
    for (std::size_t i = 0; i < 8; ++i) {
      store8(&w.rays[k + i], rays[i]);
      store8(&w.paths[k + i], records[i]);
    }
  }
  for (; k < live; ++k) {
    w.rays[k] = Ray{{ray.origin_x[k], ray.origin_y[k], ray.origin_z[k]},
                    {ray.dir_x[k], ray.dir_y[k], ray.dir_z[k]}};
    w.paths[k] = record_of(w.path, k);
  }
}

void shade(Wavefront& w, const ShadingTable& table, const Sky& sky, Vec3* radiance) {
  // Each pass: the parts it reads -> those it writes (wavefront.hpp).
  const std::size_t hits = partition(w, w.live);  // rays, hits, paths -> the same; missed
  light_misses(w, sky, w.live - hits, radiance);  // missed -> the radiance entries
  const std::size_t lanes = padded(hits);
  gather(w, table, lanes);  // rays, hits, paths, the table -> ray, sphere, path (but sky)
  surfaces(w, table.spheres(), lanes);  // ray, sphere -> surface; scatter's facing, incoming,
                                        // eta, cosine
  draw(w, hits, lanes);       // sphere, path, scatter -> drawn, reflects, redraw; path's counter
  scatter_all(w, lanes);      // sphere, scatter, path -> next ray's direction, path, alive
  spawn(w, lanes);            // surface, next ray's direction -> its origin
  w.live = compact(w, hits);  // ray, path, alive -> rays, paths
}

}  // namespace sphray::render::SPHRAY_SHADE_ISA
