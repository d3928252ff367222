// A ball resting on the book's ground, path-traced, against an independent double-precision
// reference tracer. Rays leaving a surface start at spawn()'s origin, moved along the normal by
// the surface's error bound; on the ground (radius 1000) that move is far larger than on the
// ball, so a ray leaving the ground near the contact point can start inside the ball, where it
// stays until the depth limit ends it: the contact shadow comes out darker than the geometry
// makes it (docs/robustness.md, "Touching spheres").
//
// The reference traces Lambertian spheres in double with exact ray/sphere roots and no offset:
// a ray leaving a sphere outward cannot meet that convex sphere again, so it is not tested
// against it, and a ray leaving inward takes the far root. It can also move each origin by a
// given distance along the normal, as spawn() does, so that the test can tell apart what the
// offset costs (the reference with sphray's own offset) from any other difference. The test
// asserts, over the pixels around the contact:
//  - sphray agrees with the reference given sphray's offset, within noise (the reference
//    models sphray);
//  - sphray is, within noise, at least as bright as the reference given an offset of 1e-6 of
//    each sphere's radius: whatever its offset costs, it costs no more than that.
// Both are deterministic (fixed seeds); the tolerances are in standard deviations of the Monte
// Carlo sums, estimated from the reference's own samples. Figures: the printed table.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <numbers>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "sphray/render/path_tracer.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {
namespace {

// ---------------------------------------------------------------------------------------------
// The scene: the book's ground and a ball of radius 0.5 resting on it at the origin, both
// Lambertian of albedo 0.5, under a uniform sky of radiance 1: a path's sample is 0.5^k for a
// path that escapes after k bounces, 0 for one the depth limit cuts.

constexpr int kWidth = 160, kHeight = 90;
constexpr double kSky = 1.0;
constexpr double kAlbedo = 0.5;
constexpr int kMaxDepth = 50;  // sphray's default, the book's

const CameraSpec kCamera{{0.0f, 0.3f, 2.0f}, {0.0f, 0.05f, 0.0f}, {0.0f, 1.0f, 0.0f}, 20.0f};

struct SphereSpec {
  std::array<double, 3> center;
  double radius;
};
constexpr SphereSpec kGround{{0.0, -1000.0, 0.0}, 1000.0};
constexpr SphereSpec kBall{{0.0, 0.5, 0.0}, 0.5};

Scene contact_scene() {
  Scene scene;
  scene.name = "contact";
  for (const SphereSpec& s : {kGround, kBall}) {
    scene.spheres.add({static_cast<float>(s.center[0]), static_cast<float>(s.center[1]),
                       static_cast<float>(s.center[2])},
                      static_cast<float>(s.radius));
  }
  const auto albedo = static_cast<float>(kAlbedo);
  scene.colors.assign(2, Vec3{albedo, albedo, albedo});
  scene.materials.assign(2, Material{MaterialKind::lambertian, {albedo, albedo, albedo}});
  const auto sky = static_cast<float>(kSky);
  scene.sky = Sky{{sky, sky, sky}, {sky, sky, sky}};
  scene.camera = kCamera;
  scene.width = kWidth;
  scene.height = kHeight;
  return scene;
}

// The window the statistics run over: the pixels where the ball meets the ground. The contact
// point (the origin) projects to row 51.3 at the image's centre column; the rows above it see
// the ball's underside, whose rays down land near the contact, the rows below the ground in
// front of it. All of it lies in the tile of rows 48-63 and columns 64-79 and the one to its
// right (tiles of 16), so sphray renders those two tiles alone.
constexpr int kRow0 = 50, kRow1 = 55;  // rows [kRow0, kRow1)
constexpr int kCol0 = 64, kCol1 = 96;  // columns [kCol0, kCol1)
constexpr int kTilesAcross = (kWidth + kTileSize - 1) / kTileSize;
constexpr int kRows = kRow1 - kRow0, kCols = kCol1 - kCol0;
static_assert(kRow0 / kTileSize == (kRow1 - 1) / kTileSize, "the window's rows in one tile row");
static_assert(kCol0 % kTileSize == 0 && kCol1 % kTileSize == 0, "whole tiles across");

// ---------------------------------------------------------------------------------------------
// The reference, in double.

struct D3 {
  double x, y, z;
};
D3 operator+(D3 a, D3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
D3 operator-(D3 a, D3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
D3 operator*(double s, D3 a) {
  return {s * a.x, s * a.y, s * a.z};
}
D3 operator-(D3 a) {
  return {-a.x, -a.y, -a.z};
}
double dot(D3 a, D3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
D3 cross(D3 a, D3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
D3 unit(D3 a) {
  return (1.0 / std::sqrt(dot(a, a))) * a;
}
D3 d3(Vec3 v) {
  return {v.x, v.y, v.z};
}
D3 d3(const std::array<double, 3>& a) {
  return {a[0], a[1], a[2]};
}

// SplitMix64, its own stream per (pixel, sample): every variant of the reference draws the same
// numbers for the same sample, so that their differences are those of the geometry alone.
class Random {
 public:
  explicit Random(std::uint64_t key) : state_(mix(key ^ 0x5eed'c0de'0bad'f00dull)) {}
  double uniform() {  // [0, 1), 53 bits
    state_ += 0x9e3779b97f4a7c15ull;
    return static_cast<double>(mix(state_) >> 11) * 0x1p-53;
  }

 private:
  static std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  std::uint64_t state_;
};

// The camera of render/src/frame/camera.cpp (the book's), in double: a pinhole at lookfrom, a
// viewport at distance 1 whose height follows from vfov, rows running downwards, image point
// (px, py) with pixel (x, y) covering [x, x + 1) x [y, y + 1).
class ReferenceCamera {
 public:
  ReferenceCamera(const CameraSpec& spec, int width, int height) : origin_(d3(spec.lookfrom)) {
    const double theta = static_cast<double>(spec.vfov) * std::numbers::pi / 180.0;
    const double viewport_height = 2.0 * std::tan(theta / 2.0);
    const double viewport_width = viewport_height * width / height;
    const D3 w = unit(d3(spec.lookfrom) - d3(spec.lookat));
    const D3 u = unit(cross(d3(spec.vup), w));
    const D3 v = cross(w, u);
    const D3 viewport_u = viewport_width * u, viewport_v = viewport_height * -v;
    du_ = (1.0 / width) * viewport_u;
    dv_ = (1.0 / height) * viewport_v;
    upper_left_ = -w - 0.5 * viewport_u - 0.5 * viewport_v;
  }
  D3 origin() const { return origin_; }
  D3 direction(double px, double py) const { return upper_left_ + px * du_ + py * dv_; }

 private:
  D3 origin_, upper_left_, du_, dv_;
};

struct RefSphere {
  D3 center;
  double radius;
  double offset;  // how far a ray leaving it starts from its surface, along the normal
};

// Lambertian spheres of albedo kAlbedo under the uniform sky, paths of at most kMaxDepth rays
// (the camera's included; a path still going after them brings nothing), as sphray's path mode
// defines them, with exact double roots.
class ReferenceTracer {
 public:
  ReferenceTracer(std::vector<RefSphere> spheres, const ReferenceCamera& camera)
      : spheres_(std::move(spheres)), camera_(camera) {}

  double sample(int x, int y, Random& random) const {
    const double px = x + random.uniform(), py = y + random.uniform();
    D3 origin = camera_.origin();
    D3 dir = unit(camera_.direction(px, py));
    double throughput = 1.0;
    int from = -1;         // the sphere the ray leaves, if any
    bool outward = false;  // whether it leaves that sphere outward
    for (int ray = 0; ray < kMaxDepth; ++ray) {
      int id = -1;
      const double t = nearest(origin, dir, from, outward, id);
      if (id < 0) return throughput * kSky;
      const RefSphere& s = spheres_[static_cast<std::size_t>(id)];
      // The point put back on the sphere along its normal, as sphray's surface() does.
      const D3 normal = unit(origin + t * dir - s.center);
      const D3 point = s.center + s.radius * normal;
      const D3 facing = dot(dir, normal) < 0.0 ? normal : -normal;  // the side the ray came from
      D3 next = facing + unit_vector(random);  // cosine-distributed about facing
      if (dot(next, next) < 1e-20) next = facing;
      throughput *= kAlbedo;
      outward = dot(next, normal) > 0.0;
      origin = point + (outward ? s.offset : -s.offset) * normal;
      dir = unit(next);
      from = id;
    }
    return 0.0;
  }

 private:
  static D3 unit_vector(Random& random) {
    const double z = 2.0 * random.uniform() - 1.0;
    const double phi = 2.0 * std::numbers::pi * random.uniform();
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
  }

  // The nearest sphere along the unit direction dir from origin. The sphere the ray leaves is
  // skipped when it leaves outward (a convex sphere is not met again from outside), and met at
  // its far root when it leaves inward; every other sphere at its least positive root (a far
  // root when the origin lies inside it).
  double nearest(D3 origin, D3 dir, int from, bool outward, int& id) const {
    double best = INFINITY;
    for (std::size_t i = 0; i < spheres_.size(); ++i) {
      const bool leaving = static_cast<int>(i) == from;
      if (leaving && outward) continue;
      const RefSphere& s = spheres_[i];
      // Ray Tracing Gems, chapter 7: the discriminant from the ray's closest approach, the roots
      // without cancellation.
      const D3 oc = origin - s.center;
      const double b = dot(oc, dir);
      const D3 across = oc - b * dir;
      const double disc = s.radius * s.radius - dot(across, across);
      if (disc < 0.0) continue;
      const double distance = std::sqrt(dot(oc, oc));
      const double c = (distance - s.radius) * (distance + s.radius);
      const double q = -b - std::copysign(std::sqrt(disc), b);
      const double t0 = std::min(c / q, q), t1 = std::max(c / q, q);
      const double t = leaving ? t1 : (t0 > 0.0 ? t0 : t1);
      if (t > 0.0 && t < best) {
        best = t;
        id = static_cast<int>(i);
      }
    }
    return best;
  }

  std::vector<RefSphere> spheres_;
  ReferenceCamera camera_;
};

// ---------------------------------------------------------------------------------------------
// Statistics.

// How far sphray's spawn() moves the origin of a ray leaving sphere s outward, at the point a
// ray along dir from origin meets it (s alone in the scene): the offset the reference is given
// to model sphray.
double sphray_offset(const SphereSpec& s, Vec3 origin, Vec3 dir) {
  SphereSoA one;
  one.add({static_cast<float>(s.center[0]), static_cast<float>(s.center[1]),
           static_cast<float>(s.center[2])},
          static_cast<float>(s.radius));
  const Ray ray{origin, dir};
  const Hit hit = intersect(one.view(), ray);
  EXPECT_TRUE(hit.found());
  const Surface surf = surface(one.view(), ray, hit);
  const Vec3 moved = offset_origin(surf, surf.normal) - surf.point;
  return dot(d3(moved), d3(surf.normal));
}

// Per window pixel, the mean and variance of one sample, from n samples.
struct PixelStats {
  std::vector<double> sum, squares;
  int n = 0;
  PixelStats() : sum(kRows * kCols, 0.0), squares(kRows * kCols, 0.0) {}
  void add(std::size_t i, double v) {
    sum[i] += v;
    squares[i] += v * v;
  }
  double mean(std::size_t i) const { return sum[i] / n; }
  double variance(std::size_t i) const {
    const double m = mean(i);
    return std::max(0.0, (squares[i] / n - m * m) * n / (n - 1));
  }
  // The window's sum of means, and the variance of that sum (a pixel's variance over n).
  double total() const {
    double t = 0.0;
    for (std::size_t i = 0; i < sum.size(); ++i)
      t += mean(i);
    return t;
  }
  double total_variance(int samples) const {
    double v = 0.0;
    for (std::size_t i = 0; i < sum.size(); ++i)
      v += variance(i);
    return v / samples;
  }
};

// A pixel's byte as path mode writes it (render/src/path/path_tracer.cpp, encode): gamma 2, then
// int(255.999 c) clamped.
double byte_of(double radiance) {
  return to_byte(std::sqrt(static_cast<float>(std::max(radiance, 0.0))));
}

// Samples per pixel. A sample of sphray costs a fraction of one of the reference (three
// variants in double, over the window's pixels only, against sphray's float wavefront over two
// whole tiles), hence twice as many: the comparison's variance is then a third sphray's, two
// thirds the reference's. The counts make the comparison's standard deviation small against
// the darkening an offset of 1e-6 of each radius causes (the window's darkening grows about in
// proportion to the offset, as the area of ground within the offset of the ball does), so that
// an offset of about twice the bound's, today's gamma(16) (|c_i| + r) on the ground, fails the
// bound's assertion by a wide margin rather than by chance.
constexpr int kSphraySpp = 12288;
constexpr int kReferenceSpp = 6144;
// The standard deviations each assertion allows. A normal deviate beyond 6 has probability
// 2e-9 (both tails), and still 5e-8 if the variance were underestimated by a tenth (the
// reference's sample variance stands in for sphray's, and the float renderer may differ from
// the double reference by a fraction of a deviation): a correct sphray fails with probability
// well below 1e-6. A window sum adds 160 pixels of thousands of bounded samples each, so the
// normal law holds far into its tails.
constexpr double kSigmas = 6.0;
// The offset the darkening is bounded by, as a fraction of each sphere's radius.
constexpr double kBoundOffset = 1e-6;

enum Variant { kExact, kSphrayOffset, kBound, kVariants };

TEST(ContactShadow, MatchesADoublePrecisionReferenceNearTheContact) {
  const Scene scene = contact_scene();

  // The offsets sphray's spawn() gives at the contact point: on the ground (a ray straight
  // down onto it) and on the ball's underside (a ray from its centre down).
  const double ground_offset = sphray_offset(kGround, {0, 1, 0}, {0, -1, 0});
  const double ball_offset = sphray_offset(kBall, {0, 0.5f, 0}, {0, -1, 0});
  const ReferenceCamera camera(kCamera, kWidth, kHeight);
  const auto spheres = [](double ground, double ball) {
    return std::vector<RefSphere>{{d3(kGround.center), kGround.radius, ground},
                                  {d3(kBall.center), kBall.radius, ball}};
  };
  const std::array<ReferenceTracer, kVariants> tracers = {
      ReferenceTracer(spheres(0.0, 0.0), camera),
      ReferenceTracer(spheres(ground_offset, ball_offset), camera),
      ReferenceTracer(spheres(kBoundOffset * kGround.radius, kBoundOffset * kBall.radius), camera)};
  std::array<PixelStats, kVariants> ref;
  for (PixelStats& s : ref)
    s.n = kReferenceSpp;

  // Two halves of the work on two threads, each one of sphray's tiles (a render of one tile
  // runs on one thread) and every other pixel of the reference's window; they write apart.
  std::vector<Vec3> image(static_cast<std::size_t>(kWidth) * kHeight, Vec3{0, 0, 0});
  const auto half = [&](int part) {
    // sphray: the tile alone (TileShare: the tiles t with t % count == index; the next one past
    // the image's last).
    const int tile_col = kCol0 / kTileSize + part;
    RenderOptions o;
    o.mode = Mode::path;
    o.width = kWidth;
    o.height = kHeight;
    o.spp = kSphraySpp;
    o.max_depth = kMaxDepth;
    o.threads = 1;
    const int tile = kRow0 / kTileSize * kTilesAcross + tile_col;
    o.share = TileShare{tile, tile + 1};
    const std::vector<Vec3> part_image = render_radiance(scene, o);
    for (int y = kRow0; y < kRow1; ++y) {
      for (int x = tile_col * kTileSize; x < (tile_col + 1) * kTileSize; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * kWidth + static_cast<std::size_t>(x);
        image[i] = part_image[i];
      }
    }
    // The reference: every variant draws the same numbers for the same (pixel, sample).
    for (std::size_t i = static_cast<std::size_t>(part); i < kRows * kCols; i += 2) {
      const int y = kRow0 + static_cast<int>(i) / kCols, x = kCol0 + static_cast<int>(i) % kCols;
      for (int k = 0; k < kReferenceSpp; ++k) {
        const std::uint64_t key =
            (static_cast<std::uint64_t>(y * kWidth + x) << 32) | static_cast<std::uint64_t>(k);
        for (std::size_t v = 0; v < kVariants; ++v) {
          Random random(key);
          ref[v].add(i, tracers[v].sample(x, y, random));
        }
      }
    }
  };
  std::thread other(half, 1);
  half(0);
  other.join();

  const PixelStats& exact = ref[kExact];
  const PixelStats& modelled = ref[kSphrayOffset];
  const PixelStats& bound = ref[kBound];
  const auto sphray_at = [&](int x, int y) {
    return static_cast<double>(
        image[static_cast<std::size_t>(y) * kWidth + static_cast<std::size_t>(x)].x);
  };
  double sphray_total = 0.0;
  for (int y = kRow0; y < kRow1; ++y) {
    for (int x = kCol0; x < kCol1; ++x)
      sphray_total += sphray_at(x, y);
  }
  // sphray's variance per sample is taken as the reference's with sphray's offset: the same
  // scene, offset, depth limit and estimator.
  const double sphray_variance = modelled.total_variance(kSphraySpp);
  const double sd_match = std::sqrt(sphray_variance + modelled.total_variance(kReferenceSpp));
  const double sd_bound = std::sqrt(sphray_variance + bound.total_variance(kReferenceSpp));

  // Per row, the mean byte over the window's columns, and the darkening against the exact
  // reference: sphray's, the reference's given sphray's offset (what that offset explains), and
  // the reference's given the bound's.
  std::cout << "Contact rows " << kRow0 << "-" << kRow1 - 1 << ", columns " << kCol0 << "-"
            << kCol1 - 1 << ", " << kSphraySpp << " spp (sphray), " << kReferenceSpp
            << " spp (reference). spawn() offsets: ground " << ground_offset << ", ball "
            << ball_offset << "; bound " << kBoundOffset << " of each radius.\n";
  std::printf("mean byte per row:       | darkening against exact, bytes:\n");
  std::printf("row  exact sphray ref(d) bound | sphray ref(d)  bound\n");
  std::array<double, 3> summed = {0, 0, 0};
  for (int y = kRow0; y < kRow1; ++y) {
    std::array<double, 4> b = {0, 0, 0, 0};  // exact, sphray, reference given d, bound
    for (int x = kCol0; x < kCol1; ++x) {
      const auto i = static_cast<std::size_t>((y - kRow0) * kCols + (x - kCol0));
      b[0] += byte_of(exact.mean(i));
      b[1] += byte_of(sphray_at(x, y));
      b[2] += byte_of(modelled.mean(i));
      b[3] += byte_of(bound.mean(i));
    }
    for (double& v : b)
      v /= kCols;
    std::printf("%3d %6.2f %6.2f %6.2f %5.2f | %6.2f %5.2f %6.2f\n", y, b[0], b[1], b[2], b[3],
                b[0] - b[1], b[0] - b[2], b[0] - b[3]);
    for (std::size_t k = 0; k < 3; ++k)
      summed[k] += b[0] - b[k + 1];
    RecordProperty("darkening_bytes_row" + std::to_string(y),
                   "sphray " + std::to_string(b[0] - b[1]) + ", reference given sphray's offset " +
                       std::to_string(b[0] - b[2]));
  }
  std::printf("rows' sum                  | %6.2f %5.2f %6.2f\n", summed[0], summed[1], summed[2]);
  std::printf(
      "window's radiance summed: exact %.4f, sphray %.4f, reference given d %.4f, "
      "bound %.4f\n",
      exact.total(), sphray_total, modelled.total(), bound.total());
  std::printf(
      "sphray - reference given d: %+.4f = %+.2f sd; sphray - bound: %+.4f = %+.2f sd "
      "(sd %.4f, %.4f)\n",
      sphray_total - modelled.total(), (sphray_total - modelled.total()) / sd_match,
      sphray_total - bound.total(), (sphray_total - bound.total()) / sd_bound, sd_match, sd_bound);
  std::fflush(stdout);

  // sphray agrees with the reference given its own offsets: the reference models it.
  EXPECT_LT(std::fabs(sphray_total - modelled.total()), kSigmas * sd_match)
      << "sphray's contact rows differ from the reference given sphray's own offsets";
  // Whatever its offset costs, no more than an offset of 1e-6 of each radius would.
  EXPECT_GT(sphray_total - bound.total(), -kSigmas * sd_bound)
      << "sphray's contact rows are darker than an offset of 1e-6 of each radius makes them";
}

}  // namespace
}  // namespace sphray::render
