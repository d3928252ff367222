// Kernel fuzzer: bytes become spheres and rays (NaN, infinities, denormals, huge and tiny values,
// zero radii and zero directions are all a byte away), and every instruction set this machine
// runs, the dispatched queries and the BVH of each set must
//   1. never read outside the sphere arrays: each view ends exactly where its allocation ends
//      (AddressSanitizer poisons the next byte), views of every count 0..n start at every
//      misalignment, and padded views promise exactly as much padding as exists;
//   2. keep the contract's exact rules: invalid rays miss with t == tmax, invalid spheres and
//      padding are never hit, a hit lies in (tmin, tmax), occluded() == intersect().found(),
//      count_hits() > 0 == intersect().found(), a stream equals its per-ray queries bit for
//      bit, surface() gives a unit normal, and a BVH returns bit for bit what brute force
//      returns on the same instruction set (its count_hits() too);
//   3. return the scalar reference's answer bit for bit (docs/kernel.md, "One answer on every
//      instruction set"), and pass a check against the exact geometry (long double, on the same
//      float inputs) with a float error bound (docs/robustness.md, "What agree means");
//   "Bit for bit" allows one exception everywhere: when two spheres tie at t = 0, one at +0 and
//   one at -0, a SIMD reduction keeps the lower id but may report the other's zero
//   (docs/robustness.md, the known gaps), so zeros of either sign compare equal;
//   4. in double (docs/double.md), on the same inputs scaled towards double's edges: rules 1
//      and 2 for the brute force and surface(), the double scalar reference's answer, and the
//      double tree's (built and refitted) equal to brute force's bit for bit;
//   5. answer the point queries (nearest, inside, overlapping, overlapping_pairs) in float and
//      double, by brute force and through each set's tree, as the scalar reference does.
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <span>
#include <vector>

#include <sphray/sphray.hpp>

#include "brute/validity.hpp"        // the contract's valid spheres (sphray_kernel_internals)
#include "dispatch/entry_table.hpp"  // each instruction set's entry points (sphray_kernel_internals)

namespace {

using namespace sphray;
using detail::entries_for_size;
using detail::EntryTable;
using detail::find_entries;

constexpr std::size_t kMaxSpheres = 40;
constexpr std::size_t kMaxRays = 4;

[[noreturn]] void fail(const char* what, std::size_t ray, std::size_t count, const char* impl) {
  std::fprintf(stderr, "kernel fuzzer: %s (ray %zu, view of %zu spheres, %s)\n", what, ray, count,
               impl);
  std::abort();
}

// ---------------------------------------------------------------------------------------------
// Decoding: a selector byte picks the kind of float, so every special value is one byte away.

class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : p_(data), end_(data + size) {}
  std::uint8_t byte() { return p_ < end_ ? *p_++ : 0; }
  std::uint32_t u32() {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
      v = v << 8 | byte();
    return v;
  }
  bool empty() const { return p_ >= end_; }

  float number() {
    const std::uint8_t sel = byte();
    const float sign = (sel & 0x80) ? -1.0f : 1.0f;
    switch (sel & 0x0f) {
      case 0:
        return sign * 0.0f;
      case 1:
        return std::numeric_limits<float>::quiet_NaN();
      case 2:
        return sign * INFINITY;
      case 3:  // denormal (or zero)
        return std::bit_cast<float>((sel & 0x80u) << 24 | (u32() & 0x7fffffu));
      case 4:  // huge: 2^64 .. 2^127
        return sign * std::ldexp(1.0f + byte() / 256.0f, 64 + byte() % 64);
      case 5:  // tiny normal: 2^-126 .. 2^-64
        return sign * std::ldexp(1.0f + byte() / 256.0f, -126 + byte() % 63);
      case 6:
        return std::bit_cast<float>(u32());  // anything at all
      case 7:
        return sign * static_cast<float>(byte() % 16);
      case 8:
        return sign * std::numeric_limits<float>::max();
      default: {  // ordinary geometry: 1/256 steps in [-128, 128), sometimes scaled by 2^k
        const auto fixed = static_cast<std::int16_t>(byte() << 8 | byte());
        const int scale = (sel & 0x70) == 0x70 ? static_cast<int>(byte() % 41) - 20 : 0;
        return std::ldexp(static_cast<float>(fixed) / 256.0f, scale);
      }
    }
  }
  float radius() {
    const float r = number();
    // Mostly positive, so that spheres are hit; the selector still reaches 0, -0, NaN, -inf.
    return (byte() & 3) == 0 ? r : std::fabs(r);
  }

 private:
  const std::uint8_t* p_;
  const std::uint8_t* end_;
};

struct Input {
  std::vector<float> x, y, z, r;
  std::vector<Ray> rays;
  unsigned misalign = 0;     // floats before the first sphere, from a 64-byte boundary
  bool padded = false;       // also test a view that promises padding
  std::vector<float> pad_r;  // radii of that padding (all <= 0)
  // The same spheres and rays in double: positions and radii scaled by 2^position_exponent,
  // directions by 2^direction_exponent (t by their quotient), which reaches double's own edges.
  int position_exponent = 0, direction_exponent = 0;
};

// A tracer's secondary rays start on a sphere and often leave it (nearly) tangentially, where
// the near root is a rounding of 0 (issue 17). Bytes after everything else may move a ray's
// origin onto a sphere's surface, in the direction of the decoded origin from its centre, and
// turn its direction tangent to the surface there, tilted in or out by 0 or 2^-k. Inputs that
// end earlier decode as before.
void start_on_surface(Bytes& in, Input& input, Ray& ray) {
  const std::uint8_t how = in.byte();
  if ((how & 1) == 0 || input.r.empty()) return;
  const std::size_t j = in.byte() % input.r.size();
  const Vec3 c{input.x[j], input.y[j], input.z[j]};
  const Vec3 n = normalize(ray.origin);
  if (!(length(n) > 0.5f)) return;  // the decoded origin gives no direction
  ray.origin = c + input.r[j] * n;
  if ((how & 2) == 0) return;
  const float tilt = (how & 4) ? 0.0f : std::ldexp((how & 8) ? -1.0f : 1.0f, -(in.byte() % 32));
  ray.dir = ray.dir - dot(ray.dir, n) * n + tilt * length(ray.dir) * n;
}

Input decode(const std::uint8_t* data, std::size_t size) {
  Bytes in(data, size);
  Input input;
  const std::uint8_t head = in.byte();
  const std::size_t n = in.byte() % (kMaxSpheres + 1);
  const std::size_t rays = 1 + head % kMaxRays;
  input.misalign = (head >> 2) % 16;
  input.padded = head & 0x40;
  for (std::size_t i = 0; i < rays; ++i) {
    Ray ray{{in.number(), in.number(), in.number()}, {in.number(), in.number(), in.number()}};
    const std::uint8_t bounds = in.byte();
    if (bounds & 1) ray.tmin = in.number();
    if (bounds & 2) ray.tmax = in.number();
    input.rays.push_back(ray);
  }
  for (std::size_t i = 0; i < n && !in.empty(); ++i) {
    input.x.push_back(in.number());
    input.y.push_back(in.number());
    input.z.push_back(in.number());
    input.r.push_back(in.radius());
  }
  const float never[] = {0.0f, -0.0f, -1.0f, -INFINITY, -std::numeric_limits<float>::min()};
  for (std::size_t i = 0; i < 16; ++i)
    input.pad_r.push_back(never[in.byte() % 5]);
  for (Ray& ray : input.rays)
    start_on_surface(in, input, ray);
  input.position_exponent = 4 * static_cast<std::int8_t>(in.byte());
  input.direction_exponent = 4 * static_cast<std::int8_t>(in.byte());
  return input;
}

// ---------------------------------------------------------------------------------------------
// Sphere arrays that end exactly where their allocation ends.

// Four arrays of `count` values (float or double), each preceded by `misalign` unused values
// from a 64-byte boundary, each allocated on its own with no slack: one value past the end is
// poisoned.
template <class T>
class TightArrays {
 public:
  using Columns = std::array<std::vector<T>, 4>;  // x, y, z, r

  TightArrays(const Columns& src, const std::vector<T>& pad_r, unsigned misalign, std::size_t extra,
              T pad_centre)
      : count_(src[3].size() + extra) {
    for (int k = 0; k < 4; ++k) {
      void* p = nullptr;
      const std::size_t bytes = (misalign + count_) * sizeof(T);
      if (posix_memalign(&p, 64, std::max<std::size_t>(bytes, 1)) != 0) std::abort();
      mem_[k] = static_cast<T*>(p);
      data_[k] = mem_[k] + misalign;
      std::copy(src[k].begin(), src[k].end(), data_[k]);
      for (std::size_t i = src[k].size(); i < count_; ++i)
        data_[k][i] = k == 3 ? pad_r[i - src[k].size()] : pad_centre;
    }
  }
  ~TightArrays() {
    for (T* p : mem_)
      std::free(p);
  }
  TightArrays(const TightArrays&) = delete;
  TightArrays& operator=(const TightArrays&) = delete;

  // The last `count` spheres: the view ends at the end of the allocation whatever the count.
  BasicSphereView<T> suffix(std::size_t count, std::size_t padding = 0) const {
    const std::size_t from = count_ - padding - count;
    return {data_[0] + from, data_[1] + from, data_[2] + from,
            data_[3] + from, count,           padding == 0 ? 0 : count + padding};
  }

 private:
  std::size_t count_;
  T* mem_[4] = {};
  T* data_[4] = {};
};

// ---------------------------------------------------------------------------------------------
// The exact geometry of one ray and one sphere, from the same float inputs, in long double, and
// what float arithmetic can and cannot decide about it.

using LD = long double;
constexpr LD kEps = 0x1p-24L;  // float's unit roundoff
constexpr LD kSafety = 64;     // room for every operation of either formula (about 20)

struct Truth {
  bool valid = false;       // the contract's sphere validity (an invalid sphere is never hit)
  bool resolvable = false;  // no intermediate of the float formula can overflow or underflow
  bool disc_sure = false;   // float decides hit-or-miss of the line as the exact math does
  bool line_hits = false;   // the exact discriminant is >= 0
  LD near = 0, far = 0;     // exact roots (when line_hits)
  LD tol = 0;               // bound on a float root's error, in units of t
};

bool valid_ray(const Ray& ray) {
  const float a = dot(ray.dir, ray.dir);
  return isfinite(ray.origin) && isfinite(ray.dir) && ray.tmin < ray.tmax && a >= 0x1p-126f &&
         std::isfinite(a);
}

Truth truth(const Ray& ray, float cx, float cy, float cz, float r) {
  Truth t;
  // The contract's valid sphere: a finite centre and a radius whose square is a normal float.
  t.valid =
      std::isfinite(cx) && std::isfinite(cy) && std::isfinite(cz) && r >= 0x1p-63f && r < 0x1p64f;
  if (!t.valid || !valid_ray(ray)) return t;
  const LD gx = LD{cx} - ray.origin.x, gy = LD{cy} - ray.origin.y, gz = LD{cz} - ray.origin.z;
  const LD dx = ray.dir.x, dy = ray.dir.y, dz = ray.dir.z;
  const LD a = dx * dx + dy * dy + dz * dz, len_d = std::sqrt(a);
  const LD b = gx * dx + gy * dy + gz * dz;
  const LD k = b / a;
  const LD vx = k * dx - gx, vy = k * dy - gy, vz = k * dz - gz;
  const LD dist = std::sqrt(vx * vx + vy * vy + vz * vz);  // closest approach to the centre
  const LD rr = r, disc = (rr - dist) * (rr + dist);
  const LD g = std::sqrt(gx * gx + gy * gy + gz * gz);
  // Float's error on g = c - o is relative to g itself, so the scale of the problem is the
  // larger of |g| and r, not the size of the coordinates.
  const LD scale = std::max(g, rr);
  constexpr LD kBig = LD{std::numeric_limits<float>::max()} / 1024, kSmall = 0x1p-100L;
  // The formula's intermediates are of the sizes scale^2 (disc, c), scale |d| (b, q) and
  // scale / |d| (k, the roots); it forms no |d|^2 scale^2 (q = b + sign(b) |d| sqrt(disc)).
  t.resolvable = scale * scale < kBig && scale * len_d < kBig && scale / len_d < kBig &&
                 scale * scale > kSmall && scale * len_d > kSmall && scale / len_d > kSmall;
  if (!t.resolvable) return t;
  const LD disc_err = kSafety * kEps * scale * (rr + dist + scale * 0x1p-20L);
  t.disc_sure = std::fabs(disc) > disc_err;
  t.line_hits = disc >= 0;
  if (!t.line_hits) return t;
  const LD h = std::sqrt(disc);  // half the chord
  const LD q = b + std::copysign(std::sqrt(a * disc), b);
  const LD c = (g - rr) * (g + rr);
  const LD t0 = q == 0 ? 0 : c / q, t1 = q / a;
  t.near = std::min(t0, t1);
  t.far = std::max(t0, t1);
  const LD along = std::fabs(b) / len_d;
  const LD t_scale = std::max(std::fabs(t.near), std::fabs(t.far)) * len_d + scale;
  t.tol = kSafety * kEps * t_scale * (1 + scale / h) * (1 + scale / (along + h)) / len_d;
  return t;
}

// What an implementation may answer for one sphere.
struct Allowed {
  bool must_hit = false;  // float cannot miss it
  LD latest = INFINITY;   // when must_hit: the largest t float can put that hit at
};

bool clearly_inside(LD t, LD tol, const Ray& ray) {
  return t - tol > LD{ray.tmin} && t + tol < LD{ray.tmax};
}

Allowed allowed(const Truth& s, const Ray& ray) {
  Allowed a;
  if (!s.valid || !s.resolvable || !s.disc_sure || !s.line_hits) return a;
  const LD lo = LD{ray.tmin};
  // Which root the kernel takes depends on near > tmin; close to tmin either may be taken.
  const bool near_sure_in = s.near - s.tol > lo, near_sure_out = s.near + s.tol <= lo;
  if (near_sure_in)
    a.must_hit = clearly_inside(s.near, s.tol, ray);
  else if (near_sure_out)
    a.must_hit = clearly_inside(s.far, s.tol, ray);
  a.latest = (near_sure_in ? s.near : s.far) + s.tol;
  return a;
}

bool may_hit_at(const Truth& s, const Ray& ray, float t) {
  if (!s.valid) return false;
  if (!s.resolvable || !s.disc_sure) return true;  // float cannot decide: any t in range
  if (!s.line_hits) return false;
  const LD tl = t;
  const bool near_ok = std::fabs(tl - s.near) <= s.tol && s.near + s.tol > LD{ray.tmin};
  const bool far_ok = std::fabs(tl - s.far) <= s.tol && s.near - s.tol <= LD{ray.tmin};
  return near_ok || far_ok;
}

// ---------------------------------------------------------------------------------------------
// The checks.

struct Case {
  const Ray& ray;
  std::size_t index;  // of the ray, for messages
  SphereView view;
  std::span<const Truth> truths;  // truths[i] for sphere i of the view
};

// The contract's exact rules for one answer, and its agreement with the exact geometry.
void check_hit(const Case& c, const Hit& hit, const char* impl) {
  const std::size_t n = c.view.count;
  if (!valid_ray(c.ray)) {
    if (hit.found() ||
        std::bit_cast<std::uint32_t>(hit.t) != std::bit_cast<std::uint32_t>(c.ray.tmax))
      fail("an invalid ray did not miss with t == tmax", c.index, n, impl);
    return;
  }
  if (!hit.found()) {
    if (std::bit_cast<std::uint32_t>(hit.t) != std::bit_cast<std::uint32_t>(c.ray.tmax))
      fail("a miss did not report t == tmax", c.index, n, impl);
    for (std::size_t i = 0; i < n; ++i)
      if (allowed(c.truths[i], c.ray).must_hit)
        fail("missed a sphere that float arithmetic cannot miss", c.index, n, impl);
    return;
  }
  if (hit.id >= n) fail("hit an id outside the view (padding?)", c.index, n, impl);
  if (!(hit.t > c.ray.tmin && hit.t < c.ray.tmax))
    fail("hit outside (tmin, tmax)", c.index, n, impl);
  const Truth& s = c.truths[hit.id];
  if (!s.valid) fail("hit an invalid sphere", c.index, n, impl);
  if (!may_hit_at(s, c.ray, hit.t)) fail("t is not a root of the hit sphere", c.index, n, impl);
  const LD tol = s.resolvable && s.disc_sure ? s.tol : LD{INFINITY};
  // The hit's exact t may be as low as hit.t - tol; a sphere float must hit before that is a
  // sphere the answer passed over.
  for (std::size_t i = 0; i < n; ++i) {
    const Allowed a = allowed(c.truths[i], c.ray);
    if (i != hit.id && a.must_hit && a.latest < LD{hit.t} - tol)
      fail("a clearly closer sphere was passed over", c.index, n, impl);
  }
}

void check_surface(const Case& c, const Hit& hit, const char* impl) {
  if (!hit.found()) return;
  const Surface s = surface(c.view, c.ray, hit);
  const LD len = std::sqrt(LD{s.normal.x} * s.normal.x + LD{s.normal.y} * s.normal.y +
                           LD{s.normal.z} * s.normal.z);
  if (!(std::fabs(len - 1) <= 1e-5L)) {
    const std::uint32_t k = hit.id;
    std::fprintf(stderr, "ray %a %a %a dir %a %a %a; sphere %a %a %a r %a; t %a; normal %a %a %a\n",
                 c.ray.origin.x, c.ray.origin.y, c.ray.origin.z, c.ray.dir.x, c.ray.dir.y,
                 c.ray.dir.z, c.view.cx[k], c.view.cy[k], c.view.cz[k], c.view.radius[k], hit.t,
                 s.normal.x, s.normal.y, s.normal.z);
    fail("surface() normal is not unit length", c.index, c.view.count, impl);
  }
}

bool same(const Hit& a, const Hit& b) {
  return a.id == b.id && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t);
}

// The same id and the same t, where -0 equals +0: the tree and brute force may reach a zero t
// through different lanes of min/max, which do not order zeros.
bool equal(const Hit& a, const Hit& b) {
  return a.id == b.id && (a.t == b.t || (std::isnan(a.t) && std::isnan(b.t)));
}

void expect_equal(const Hit& a, const Hit& b, const char* what, std::size_t ray, std::size_t count,
                  const char* impl) {
  if (equal(a, b)) return;
  std::fprintf(stderr, "id %u t %a against id %u t %a\n", a.id, a.t, b.id, b.t);
  fail(what, ray, count, impl);
}

struct Tally {
  unsigned long long answers = 0, equal_to_scalar = 0;
  unsigned long long bvh_answers = 0, bvh_undecidable_differs = 0;
};
Tally tally;

void check_kernel(const EntryTable& k, const std::vector<Ray>& rays, SphereView view,
                  const std::vector<std::vector<Truth>>& truths, std::size_t first) {
  const char* name = isa_name(k.isa).data();
  std::vector<Hit> stream(rays.size());
  k.intersect_stream(view, rays.data(), stream.data(), rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Case c{rays[i], i, view, std::span(truths[i]).subspan(first, view.count)};
    const Hit hit = k.intersect(view, rays[i]);
    expect_equal(hit, stream[i], "stream differs from the per-ray query", i, view.count, name);
    if (k.occluded(view, rays[i]) != hit.found())
      fail("occluded() differs from intersect().found()", i, view.count, name);
    if ((k.intersect_all(view, rays[i], nullptr, nullptr, 0) > 0) != hit.found())
      fail("count_hits() > 0 differs from intersect().found()", i, view.count, name);
    check_hit(c, hit, name);
    check_surface(c, hit, name);
    // docs/kernel.md, "One answer on every instruction set": the scalar reference's bits
    // (zeros of either sign equal: the lanes' minimum does not order them).
    const Hit ref = scalar::intersect(view, rays[i]);
    expect_equal(hit, ref, "differs from the scalar reference", i, view.count, name);
    ++tally.answers;
    tally.equal_to_scalar += same(hit, ref);
  }
}

// Whether float arithmetic decides every sphere for this ray: no overflow or underflow, and
// no ray within rounding of grazing a sphere.
bool decidable(std::span<const Truth> truths) {
  for (const Truth& s : truths)
    if (s.valid && (!s.resolvable || !s.disc_sure)) return false;
  return true;
}

// A tree must answer what brute force answers on the same set, bit for bit, wherever float
// decides every sphere. Where it does not (a sphere so small or so far that its square leaves
// float's range, a ray grazing within rounding), the brute-force kernel's answer is itself
// rounding noise, which the box test cannot reproduce; the tree's answer must then pass the
// same checks as every other answer.
void check_bvh(const EntryTable& k, const std::vector<Ray>& rays, SphereView view,
               const std::vector<std::vector<Truth>>& truths, const SphereBVH& bvh) {
  const char* name = isa_name(k.isa).data();
  std::vector<Hit> stream(rays.size());
  intersect(bvh, rays, stream);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit brute = k.intersect(view, rays[i]);
    const Hit tree = intersect(bvh, rays[i]);
    expect_equal(tree, stream[i], "the BVH stream differs from its per-ray query", i, view.count,
                 name);
    if (occluded(bvh, rays[i]) != tree.found())
      fail("the BVH's occluded() differs from its intersect()", i, view.count, name);
    const std::size_t tree_count = count_hits(bvh, rays[i]);
    if ((tree_count > 0) != tree.found())
      fail("the BVH's count_hits() > 0 differs from its intersect()", i, view.count, name);
    check_hit({rays[i], i, view, truths[i]}, tree, name);
    ++tally.bvh_answers;
    if (decidable(truths[i])) {
      expect_equal(tree, brute, "the BVH differs from brute force on its set", i, view.count, name);
      if (tree_count != k.intersect_all(view, rays[i], nullptr, nullptr, 0))
        fail("the BVH's count_hits() differs from brute force's", i, view.count, name);
    } else if (!same(tree, brute))
      ++tally.bvh_undecidable_differs;
  }
}

// ---------------------------------------------------------------------------------------------
// Point queries, in float and double: each kernel's brute force and the tree of its set against
// the scalar reference, bit for bit, at the rays' origins and ends and at the spheres' centres;
// the balls of the rays' tmax (or of a sphere's radius); the tree's overlapping pairs against
// the pairs scalar::overlapping lists.

template <class S>
bool same_bits(S a, S b) {
  return std::memcmp(&a, &b, sizeof(S)) == 0;
}

template <class S>
bool same(const BasicNearest<S>& a, const BasicNearest<S>& b) {
  return a.id == b.id && same_bits(a.distance, b.distance) && same_bits(a.point.x, b.point.x) &&
         same_bits(a.point.y, b.point.y) && same_bits(a.point.z, b.point.z);
}

template <class S>
void check_point(const EntryTable& k, BasicSphereView<S> view, const BasicSphereBVH<S>& bvh,
                 BasicVec3<S> p, S radius, std::size_t i) {
  const char* name = isa_name(k.isa).data();
  const BasicNearest<S> want = scalar::nearest(view, p);
  const BasicHit<S> brute =
      detail::in_precision<S>(k.nearest, k.nearest_d)(view, p, std::numeric_limits<S>::infinity());
  if (brute.id != want.id || (want.found() && !same_bits(brute.t, want.distance)))
    fail("point: the nearest sphere differs from the scalar reference's", i, view.count, name);
  if (!same(nearest(bvh, p), want))
    fail("point: the tree's nearest sphere differs from the scalar reference's", i, view.count,
         name);
  if (inside(bvh, p) != (want.found() && want.distance < 0))
    fail("point: the tree's inside() differs from the nearest distance's sign", i, view.count,
         name);
  std::vector<std::uint32_t> got(view.count + 1), expected(view.count + 1);
  const std::size_t total = scalar::overlapping(view, p, radius, expected);
  if (overlapping(bvh, p, radius, got) != total ||
      !std::equal(got.begin(), got.begin() + static_cast<std::ptrdiff_t>(total), expected.begin()))
    fail("point: the tree's overlapping() differs from the scalar reference's", i, view.count,
         name);
}

template <class S>
void check_points(const EntryTable& k, BasicSphereView<S> view, const BasicSphereBVH<S>& bvh,
                  const std::vector<BasicRay<S>>& rays) {
  std::size_t i = 0;
  for (const BasicRay<S>& r : rays) {
    const S radius = std::isfinite(r.tmax) ? std::fabs(r.tmax) : S(0);
    check_point(k, view, bvh, r.origin, radius, i);
    check_point(k, view, bvh, r.origin + r.dir, radius, i++);
  }
  for (std::size_t s = 0; s < view.count; ++s)
    check_point(k, view, bvh, {view.cx[s], view.cy[s], view.cz[s]}, view.radius[s], s);

  // The pairs: for each valid sphere i, the valid j > i that the ball of sphere i overlaps.
  std::vector<IdPair> want, got;
  std::vector<std::uint32_t> ids(view.count);
  for (std::uint32_t a = 0; a < view.count; ++a) {
    const BasicVec3<S> c{view.cx[a], view.cy[a], view.cz[a]};
    if (!detail::valid_sphere(c, view.radius[a])) continue;
    const std::size_t n = scalar::overlapping(view, c, view.radius[a], ids);
    for (std::size_t j = 0; j < n; ++j)
      if (ids[j] > a) want.push_back({a, ids[j]});
  }
  overlapping_pairs(bvh, got);
  const auto order = [](IdPair a, IdPair b) {
    return a.first != b.first ? a.first < b.first : a.second < b.second;
  };
  std::sort(got.begin(), got.end(), order);
  if (got != want)
    fail("point: the tree's overlapping pairs differ from the reference's", 0, view.count,
         isa_name(k.isa).data());
}

// ---------------------------------------------------------------------------------------------
// Double precision: the same inputs scaled into double's range, every instruction set's double
// kernel against the double scalar reference bit for bit, and the contract's exact rules.

bool valid_ray(const Rayd& ray) {
  const double a = dot(ray.dir, ray.dir);
  return isfinite(ray.origin) && isfinite(ray.dir) && ray.tmin < ray.tmax &&
         a >= std::numeric_limits<double>::min() && std::isfinite(a);
}

bool valid_sphere(const SphereViewd& v, std::size_t i) {
  return std::isfinite(v.cx[i]) && std::isfinite(v.cy[i]) && std::isfinite(v.cz[i]) &&
         v.radius[i] >= 0x1p-511 && v.radius[i] < 0x1p512;
}

bool equal(const Hitd& a, const Hitd& b) {
  return a.id == b.id && (a.t == b.t || (std::isnan(a.t) && std::isnan(b.t)));
}

void check_double_hit(const Rayd& ray, const SphereViewd& v, const Hitd& hit, std::size_t i,
                      const char* name) {
  const bool tmax_bits =
      std::bit_cast<std::uint64_t>(hit.t) == std::bit_cast<std::uint64_t>(ray.tmax);
  if (!valid_ray(ray) && (hit.found() || !tmax_bits))
    fail("double: an invalid ray did not miss with t == tmax", i, v.count, name);
  if (!hit.found()) {
    if (!tmax_bits) fail("double: a miss did not report t == tmax", i, v.count, name);
    return;
  }
  if (hit.id >= v.count) fail("double: hit an id outside the view", i, v.count, name);
  if (!(hit.t > ray.tmin && hit.t < ray.tmax))
    fail("double: hit outside (tmin, tmax)", i, v.count, name);
  if (!valid_sphere(v, hit.id)) fail("double: hit an invalid sphere", i, v.count, name);
  const Surfaced s = surface(v, ray, hit);
  const LD len = std::sqrt(LD{s.normal.x} * s.normal.x + LD{s.normal.y} * s.normal.y +
                           LD{s.normal.z} * s.normal.z);
  if (!(std::fabs(len - 1) <= 1e-12L))
    fail("double: surface() normal is not unit length", i, v.count, name);
}

void check_double_kernel(const EntryTable& k, const std::vector<Rayd>& rays,
                         const SphereViewd& view) {
  const char* name = isa_name(k.isa).data();
  std::vector<Hitd> stream(rays.size());
  k.intersect_stream_d(view, rays.data(), stream.data(), rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hitd hit = k.intersect_d(view, rays[i]);
    if (!equal(hit, stream[i]))
      fail("double: stream differs from the per-ray query", i, view.count, name);
    if (k.occluded_d(view, rays[i]) != hit.found())
      fail("double: occluded() differs from intersect().found()", i, view.count, name);
    if (!equal(hit, scalar::intersect(view, rays[i])))
      fail("double: differs from the scalar reference", i, view.count, name);
    if (!equal(hit, intersect(view, rays[i])))
      fail("double: the dispatched query differs from its kernels", i, view.count, name);
    check_double_hit(rays[i], view, hit, i, name);
  }
}

// The double tree over the whole view, built for k's instruction set and refitted: brute
// force's answer in double, bit for bit. Its float boxes are rounded outward from every double
// sphere, so it can lose no sphere brute force hits, and its leaves compute the same roots.
void check_double_bvh(const EntryTable& k, const std::vector<Rayd>& rays, const SphereViewd& view,
                      const SphereBVHd& bvh) {
  const char* name = isa_name(k.isa).data();
  std::vector<Hitd> stream(rays.size());
  intersect(bvh, rays, stream);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hitd tree = intersect(bvh, rays[i]);
    if (const Hitd brute = k.intersect_d(view, rays[i]); !equal(tree, brute)) {
      std::fprintf(stderr, "id %u t %a against id %u t %a\n", tree.id, tree.t, brute.id, brute.t);
      fail("double: the BVH differs from brute force", i, view.count, name);
    }
    if (!equal(tree, stream[i]))
      fail("double: the BVH stream differs from its per-ray query", i, view.count, name);
    if (occluded(bvh, rays[i]) != tree.found())
      fail("double: the BVH's occluded() differs from its intersect()", i, view.count, name);
    if (count_hits(bvh, rays[i]) != k.intersect_all_d(view, rays[i], nullptr, nullptr, 0))
      fail("double: the BVH's count_hits() differs from brute force's", i, view.count, name);
    ++tally.bvh_answers;
  }
}

void check_double(const Input& in, const std::vector<const EntryTable*>& kernels) {
  const int e = in.position_exponent, ed = in.direction_exponent;
  const auto scaled = [](const std::vector<float>& from, int exponent) {
    std::vector<double> to;
    for (const float x : from)
      to.push_back(std::ldexp(static_cast<double>(x), exponent));
    return to;
  };
  const std::vector<double> pad_r(in.pad_r.begin(), in.pad_r.end());
  std::vector<Rayd> rays;
  for (const Ray& r : in.rays) {
    const auto at = [](Vec3 v, int exponent) {
      return Vec3d{std::ldexp(static_cast<double>(v.x), exponent),
                   std::ldexp(static_cast<double>(v.y), exponent),
                   std::ldexp(static_cast<double>(v.z), exponent)};
    };
    rays.push_back({at(r.origin, e), at(r.dir, ed), std::ldexp(static_cast<double>(r.tmin), e - ed),
                    std::ldexp(static_cast<double>(r.tmax), e - ed), r.mask});
  }
  const TightArrays<double>::Columns columns{scaled(in.x, e), scaled(in.y, e), scaled(in.z, e),
                                             scaled(in.r, e)};
  const std::size_t n = in.r.size();
  const TightArrays<double> tight(columns, pad_r, in.misalign % 8, 0, 0.0);
  for (std::size_t m = 0; m <= n; ++m)
    for (const EntryTable* k : kernels)
      check_double_kernel(*k, rays, tight.suffix(m));
  if (in.padded) {
    const std::size_t padding = (16 - n % 16) % 16;
    const TightArrays<double> padded(columns, pad_r, in.misalign % 8, padding,
                                     columns[0].empty() ? NAN : columns[0].back());
    for (const EntryTable* k : kernels)
      check_double_kernel(*k, rays, padded.suffix(n, padding));
  }
  const auto backwards = [](const std::vector<double>& v) {
    return std::vector<double>(v.rbegin(), v.rend());
  };
  const TightArrays<double>::Columns reversed{backwards(columns[0]), backwards(columns[1]),
                                              backwards(columns[2]), backwards(columns[3])};
  const TightArrays<double> tight_reversed(reversed, pad_r, in.misalign % 8, 0, 0.0);
  for (const EntryTable* k : kernels) {
    SphereBVHd bvh(tight.suffix(n), k->isa, BvhBuildOptions{1});
    check_double_bvh(*k, rays, tight.suffix(n), bvh);
    check_points(*k, tight.suffix(n), bvh, rays);
    bvh.refit(tight_reversed.suffix(n));
    check_double_bvh(*k, rays, tight_reversed.suffix(n), bvh);
    check_points(*k, tight_reversed.suffix(n), bvh, rays);
  }
}

void report() {
  std::fprintf(stderr,
               "kernel fuzzer: %llu answers checked, %llu equal to the scalar reference bit for "
               "bit (the others: a zero t of the other sign); %llu BVH answers, %llu of them "
               "(rays float cannot decide) differing from brute force\n",
               tally.answers, tally.equal_to_scalar, tally.bvh_answers,
               tally.bvh_undecidable_differs);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::atexit(report);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Input in = decode(data, size);
  const std::size_t n = in.r.size();
  // truths[ray][sphere], computed once for the n spheres; a view of the last m spheres uses
  // the entries from n - m on.
  std::vector<std::vector<Truth>> truths(in.rays.size());
  for (std::size_t i = 0; i < in.rays.size(); ++i)
    for (std::size_t s = 0; s < n; ++s)
      truths[i].push_back(truth(in.rays[i], in.x[s], in.y[s], in.z[s], in.r[s]));

  const TightArrays<float> tight({in.x, in.y, in.z, in.r}, in.pad_r, in.misalign, 0, 0.0f);
  std::vector<const EntryTable*> kernels;
  for (Isa isa : supported_isas())
    kernels.push_back(find_entries(isa));

  for (std::size_t m = 0; m <= n; ++m) {
    const SphereView view = tight.suffix(m);
    for (const EntryTable* k : kernels)
      check_kernel(*k, in.rays, view, truths, n - m);
    for (std::size_t i = 0; i < in.rays.size(); ++i)
      if (!same(intersect(view, in.rays[i]), entries_for_size(m).intersect(view, in.rays[i])))
        fail("the dispatched query differs from its kernel", i, m, "dispatch");
  }

  // A view that promises padding, the padding being exactly as long as promised, with
  // never-hit spheres whose centres are anything at all.
  if (in.padded) {
    const std::size_t padding = (16 - n % 16) % 16;
    const TightArrays<float> padded({in.x, in.y, in.z, in.r}, in.pad_r, in.misalign, padding,
                                    in.x.empty() ? NAN : in.x.back());
    for (const EntryTable* k : kernels)
      check_kernel(*k, in.rays, padded.suffix(n, padding), truths, 0);
  }

  check_double(in, kernels);

  // The BVH of each set, built over the whole view, then refitted to the spheres in reverse
  // order (same count): both must answer exactly what brute force answers.
  std::vector<float> rx(in.x.rbegin(), in.x.rend()), ry(in.y.rbegin(), in.y.rend()),
      rz(in.z.rbegin(), in.z.rend()), rr(in.r.rbegin(), in.r.rend());
  const SphereView reversed{rx.data(), ry.data(), rz.data(), rr.data(), n};
  std::vector<std::vector<Truth>> reversed_truths(in.rays.size());
  for (std::size_t i = 0; i < in.rays.size(); ++i)
    reversed_truths[i].assign(truths[i].rbegin(), truths[i].rend());
  for (const EntryTable* k : kernels) {
    SphereBVH bvh(tight.suffix(n), k->isa, BvhBuildOptions{1});
    check_bvh(*k, in.rays, tight.suffix(n), truths, bvh);
    check_points(*k, tight.suffix(n), bvh, in.rays);
    bvh.refit(reversed);
    check_bvh(*k, in.rays, reversed, reversed_truths, bvh);
    check_points(*k, reversed, bvh, in.rays);
  }
  return 0;
}
