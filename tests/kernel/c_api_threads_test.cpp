// The C API and threads. Every query on several threads (sphray_query_args.threads) gives the
// single thread's results, bit for bit, in the same places. And sphray_scene_refit while other
// threads query the same scene (issue 30: a brute-force scene segfaulted, its spheres freed
// under the readers): a refit now writes the scene's spheres in place, so a query that overlaps
// it sees each value old or new, never freed memory, and the queries after it see the new
// spheres exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <sphray/sphray.h>

#if defined(__linux__)
#include <malloc.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

namespace {

// ---- Queries on several threads ----

// sphray.h's chunk of work: rays and points are shared out 4096 at a time. Five chunks and a
// partial one, so that 2 and 3 threads each take several, in an order that varies run to run.
constexpr std::size_t kChunk = 4096;
constexpr std::size_t kMany = 5 * kChunk + 1234;
// Up to 80 crossings per ray are kept: more than the 64 gathered on the stack, so every thread
// needs a heap buffer of its own. The shells below give some rays more than 80.
constexpr std::size_t kHeapSlots = 80;
constexpr std::size_t kShells = 48;

// Random spheres around the origin, and kShells concentric shells at the origin (radii 0.2 to
// 9.6): a ray through the middle crosses dozens of surfaces. Sphere masks of one of three bits.
struct Cloud {
  std::vector<float> cx, cy, cz, r;
  std::vector<std::uint32_t> masks;
};

Cloud cloud(std::size_t random_spheres, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-10.0f, 10.0f), rad(0.2f, 0.8f);
  Cloud c;
  for (std::size_t i = 0; i < random_spheres + kShells; ++i) {
    const bool shell = i < kShells;
    c.cx.push_back(shell ? 0.0f : pos(rng));
    c.cy.push_back(shell ? 0.0f : pos(rng));
    c.cz.push_back(shell ? 0.0f : pos(rng));
    c.r.push_back(shell ? 0.2f * static_cast<float>(i + 1) : rad(rng));
    c.masks.push_back(1u << (rng() % 3));
  }
  return c;
}

// Rays from a box around the cloud: every third one aimed near the centre (through many
// shells), the others anywhere; some with a finite tmax or a positive tmin. Each with a mask of
// 0 (sees nothing) to all three bits.
struct Rays {
  std::vector<sphray_ray> rays;
  std::vector<std::uint32_t> masks;
  std::vector<float> ox, oy, oz, dx, dy, dz, tmin, tmax;  // the same rays, as arrays
};

Rays many_rays(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> box(-12.0f, 12.0f), unit(-1.0f, 1.0f);
  Rays out;
  for (std::size_t i = 0; i < kMany; ++i) {
    sphray_ray r{box(rng), box(rng), box(rng), unit(rng), unit(rng), unit(rng), 0.0f, INFINITY};
    if (i % 3 == 0) {
      r.dx = unit(rng) - r.ox, r.dy = unit(rng) - r.oy, r.dz = unit(rng) - r.oz;
    }
    if (i % 7 == 1) r.tmax = 0.5f + std::abs(unit(rng));
    if (i % 11 == 2) r.tmin = std::abs(unit(rng));
    out.rays.push_back(r);
    out.masks.push_back(static_cast<std::uint32_t>(rng() % 8));
    out.ox.push_back(r.ox), out.oy.push_back(r.oy), out.oz.push_back(r.oz);
    out.dx.push_back(r.dx), out.dy.push_back(r.dy), out.dz.push_back(r.dz);
    out.tmin.push_back(r.tmin), out.tmax.push_back(r.tmax);
  }
  return out;
}

// The bytes of a query's outputs, for comparing whole answers at once.
template <class T>
void append(std::vector<unsigned char>& bytes, const std::vector<T>& values) {
  const auto* begin = reinterpret_cast<const unsigned char*>(values.data());
  bytes.insert(bytes.end(), begin, begin + values.size() * sizeof(T));
}

// Where two answers first differ, for the failure message.
std::string first_difference(const std::vector<unsigned char>& a,
                             const std::vector<unsigned char>& b) {
  if (a.size() != b.size())
    return "sizes " + std::to_string(a.size()) + " and " + std::to_string(b.size());
  const auto diff = std::mismatch(a.begin(), a.end(), b.begin());
  return diff.first == a.end() ? "none" : "byte " + std::to_string(diff.first - a.begin());
}

// One query over all the rays (or points) with the given args, its outputs as bytes. Every
// output starts as the same pattern, so that a slot one call writes and another leaves shows.
using Query = std::function<std::vector<unsigned char>(const sphray_query_args*)>;

struct NamedQuery {
  std::string name;
  bool rays;  // false: a point query, which takes no masks
  Query run;
};

std::vector<NamedQuery> every_query(sphray_scene* scene, const Rays& in,
                                    const std::vector<float>& points) {
  const sphray_ray* rays = in.rays.data();
  const std::size_t n = in.rays.size();
  std::vector<NamedQuery> queries;
  queries.push_back({"intersect", true, [=](const sphray_query_args* args) {
                       std::vector<sphray_hit> hits(n, sphray_hit{-1.0f, 7});
                       EXPECT_EQ(sphray_intersect(scene, rays, n, hits.data(), args), SPHRAY_OK)
                           << sphray_last_error();
                       std::vector<unsigned char> bytes;
                       append(bytes, hits);
                       return bytes;
                     }});
  queries.push_back({"occluded", true, [=](const sphray_query_args* args) {
                       std::vector<unsigned char> occluded(n, 9);
                       EXPECT_EQ(sphray_occluded(scene, rays, n, occluded.data(), args), SPHRAY_OK)
                           << sphray_last_error();
                       return occluded;
                     }});
  // Laid out as sphray_hit, so that its answers compare with sphray_intersect's.
  queries.push_back(
      {"intersect_arrays", true, [=, &in](const sphray_query_args* args) {
         const sphray_ray_arrays arrays{in.ox.data(), in.oy.data(), in.oz.data(),   in.dx.data(),
                                        in.dy.data(), in.dz.data(), in.tmin.data(), in.tmax.data()};
         std::vector<float> t(n, -1.0f);
         std::vector<std::uint32_t> id(n, 7);
         EXPECT_EQ(sphray_intersect_arrays(scene, &arrays, n, t.data(), id.data(), args), SPHRAY_OK)
             << sphray_last_error();
         std::vector<sphray_hit> hits(n);
         for (std::size_t i = 0; i < n; ++i)
           hits[i] = {t[i], id[i]};
         std::vector<unsigned char> bytes;
         append(bytes, hits);
         return bytes;
       }});
  // Every crossing and the nearest ones, on the stack (3 slots) and in heap buffers (80).
  for (const std::size_t slots : {std::size_t{3}, kHeapSlots}) {
    for (const bool nearest : {false, true}) {
      const auto call = nearest ? sphray_intersect_nearest : sphray_intersect_all;
      queries.push_back(
          {std::string(nearest ? "intersect_nearest" : "intersect_all") + ", " +
               std::to_string(slots) + " slots",
           true, [=](const sphray_query_args* args) {
             std::vector<sphray_hit> hits(n * slots, sphray_hit{-1.0f, 7});
             std::vector<unsigned char> exits(n * slots, 9);
             std::vector<size_t> counts(n, 99);
             EXPECT_EQ(call(scene, rays, n, slots, hits.data(), exits.data(), counts.data(), args),
                       SPHRAY_OK)
                 << sphray_last_error();
             std::vector<unsigned char> bytes;
             append(bytes, hits);
             append(bytes, exits);
             append(bytes, counts);
             return bytes;
           }});
    }
  }
  queries.push_back({"count_hits", true, [=](const sphray_query_args* args) {
                       std::vector<size_t> counts(n, 99);
                       EXPECT_EQ(sphray_count_hits(scene, rays, n, counts.data(), args), SPHRAY_OK)
                           << sphray_last_error();
                       std::vector<unsigned char> bytes;
                       append(bytes, counts);
                       return bytes;
                     }});
  const float* p = points.data();
  const std::size_t m = points.size() / 3;
  for (const float max_distance : {0.5f, INFINITY}) {
    queries.push_back(
        {"nearest within " + std::to_string(max_distance), false,
         [=](const sphray_query_args* args) {
           std::vector<sphray_nearest_sphere> out(m, {7, -1.0f, -1.0f, -1.0f, -1.0f});
           EXPECT_EQ(sphray_nearest(scene, p, m, max_distance, out.data(), args), SPHRAY_OK)
               << sphray_last_error();
           std::vector<unsigned char> bytes;
           append(bytes, out);
           return bytes;
         }});
  }
  queries.push_back({"inside", false, [=](const sphray_query_args* args) {
                       std::vector<unsigned char> inside(m, 9);
                       EXPECT_EQ(sphray_inside(scene, p, m, inside.data(), args), SPHRAY_OK)
                           << sphray_last_error();
                       return inside;
                     }});
  return queries;
}

// Every query, on 0 (the calling thread), 2, 3 and one thread per core, with and without ray
// masks: the one-thread call's bytes each time. Then checks that the answers are not trivial:
// the masks change some, rays do cross more surfaces than the heap slots hold, and the arrays
// form answers as sphray_intersect does.
void expect_any_thread_count_gives_the_same_bits(int accel, std::size_t random_spheres) {
  const Cloud c = cloud(random_spheres, 3);
  sphray_scene_args scene_args = SPHRAY_SCENE_ARGS_INIT;
  scene_args.accel = accel;
  sphray_scene* scene = nullptr;
  ASSERT_EQ(sphray_scene_create(c.cx.data(), c.cy.data(), c.cz.data(), c.r.data(), c.cx.size(), 0,
                                &scene_args, &scene),
            SPHRAY_OK)
      << sphray_last_error();
  ASSERT_EQ(sphray_scene_set_masks(scene, c.masks.data(), 0), SPHRAY_OK);
  const Rays rays = many_rays(5);
  std::vector<float> points;  // the rays' origins, and points along them through the shells
  for (std::size_t i = 0; i < kMany; ++i) {
    const sphray_ray& r = rays.rays[i];
    const float s = i % 2 == 0 ? 0.0f : 0.9f;
    points.insert(points.end(), {r.ox + s * r.dx, r.oy + s * r.dy, r.oz + s * r.dz});
  }
  std::vector<std::vector<unsigned char>> plain, masked;  // one thread's answers, per query
  for (const NamedQuery& q : every_query(scene, rays, points)) {
    for (const bool with_masks : {false, true}) {
      if (with_masks && !q.rays) continue;
      SCOPED_TRACE(q.name + (with_masks ? ", masks" : ""));
      sphray_query_args args = SPHRAY_QUERY_ARGS_INIT;
      args.masks = with_masks ? rays.masks.data() : nullptr;
      args.threads = 1;
      const std::vector<unsigned char> want = q.run(&args);
      (with_masks ? masked : plain).push_back(want);
      if (!with_masks) {
        const std::vector<unsigned char> defaults = q.run(nullptr);
        ASSERT_TRUE(defaults == want) << "NULL args: " << first_difference(defaults, want);
      }
      for (const unsigned threads : {0u, 2u, 3u, SPHRAY_THREADS_ALL}) {
        args.threads = threads;
        const std::vector<unsigned char> got = q.run(&args);
        ASSERT_TRUE(got == want) << threads
                                 << " threads, first difference: " << first_difference(got, want);
      }
    }
  }
  // The ray queries, in plain and masked alike: intersect (0), occluded (1), intersect_arrays
  // (2), the four crossing queries (3 to 6), count_hits (7).
  ASSERT_EQ(masked.size(), 8u);
  EXPECT_TRUE(plain[0] != masked[0]) << "the masks hide nothing";
  EXPECT_TRUE(plain[2] == plain[0]) << "intersect_arrays: " << first_difference(plain[2], plain[0]);
  EXPECT_TRUE(masked[2] == masked[0])
      << "intersect_arrays, masks: " << first_difference(masked[2], masked[0]);
  std::vector<size_t> counts(kMany);
  std::memcpy(counts.data(), plain[7].data(), kMany * sizeof(size_t));
  EXPECT_GT(*std::max_element(counts.begin(), counts.end()), kHeapSlots);
  const std::size_t hit = static_cast<std::size_t>(
      std::count_if(counts.begin(), counts.end(), [](size_t n) { return n > 0; }));
  EXPECT_GT(hit, kMany / 4) << "the rays do cross spheres";
  EXPECT_EQ(sphray_scene_release(scene), SPHRAY_OK);
}

TEST(CApiThreads, EveryQueryGivesTheSameBitsOnAnyThreadCountBruteForce) {
  expect_any_thread_count_gives_the_same_bits(SPHRAY_ACCEL_BRUTE, 100);
}

TEST(CApiThreads, EveryQueryGivesTheSameBitsOnAnyThreadCountBvh) {
  expect_any_thread_count_gives_the_same_bits(SPHRAY_ACCEL_BVH, 3000);
}

// The overlap is a data race by the C++ memory model's letter, and documented as such
// (sphray.h): ThreadSanitizer reports it, so the case is left out of that build.
#if defined(__linux__) && !defined(__SANITIZE_THREAD__)

constexpr std::size_t kSpheres = 20000;
constexpr std::size_t kRays = 256;
constexpr int kRefits = 2000;

struct Spheres {
  std::vector<float> cx, cy, cz, r;
};

// Two placements of the same spheres; the refits alternate between them.
Spheres placement(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-20.0f, 20.0f), rad(0.05f, 0.3f);
  Spheres s;
  for (std::size_t i = 0; i < kSpheres; ++i) {
    s.cx.push_back(pos(rng));
    s.cy.push_back(pos(rng));
    s.cz.push_back(pos(rng));
    s.r.push_back(rad(rng));
  }
  return s;
}

std::vector<sphray_ray> some_rays() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<sphray_ray> rays;
  for (std::size_t i = 0; i < kRays; ++i)
    rays.push_back({u(rng), u(rng), u(rng), u(rng), u(rng), u(rng) + 2.0f, 0.0f, INFINITY});
  return rays;
}

// Every query that reads the spheres, once over the rays; false on any status but SPHRAY_OK or
// an id outside the scene.
bool query_once(sphray_scene* scene, const std::vector<sphray_ray>& rays) {
  std::vector<sphray_hit> hits(rays.size());
  std::vector<unsigned char> blocked(rays.size());
  std::vector<sphray_hit_surface> surfaces(rays.size());
  std::vector<size_t> counts(rays.size());
  std::vector<sphray_nearest_sphere> nearest(rays.size());
  std::vector<float> points;
  for (const sphray_ray& ray : rays) {
    points.push_back(ray.ox);
    points.push_back(ray.oy);
    points.push_back(ray.oz);
  }
  const std::size_t n = rays.size();
  if (sphray_intersect(scene, rays.data(), n, hits.data(), nullptr) != SPHRAY_OK ||
      sphray_occluded(scene, rays.data(), n, blocked.data(), nullptr) != SPHRAY_OK ||
      sphray_surface(scene, rays.data(), hits.data(), n, surfaces.data()) != SPHRAY_OK ||
      sphray_count_hits(scene, rays.data(), n, counts.data(), nullptr) != SPHRAY_OK ||
      sphray_nearest(scene, points.data(), n, INFINITY, nearest.data(), nullptr) != SPHRAY_OK)
    return false;
  for (const sphray_hit& h : hits)
    if (h.id != SPHRAY_NO_HIT && h.id >= kSpheres) return false;
  return true;
}

// In a child process: two threads query the scene while this one refits it kRefits times, then
// the scene's answers must be a new scene's of the last placement, bit for bit. Exit codes:
// 0 passed, 1 a query failed, 2 a refit failed, 3 the answers after the refits differ. Arrays
// above 64 KiB are given their own mapping and unmapped when freed (glibc otherwise raises
// that threshold as it frees them), so a read of freed spheres faults rather than reads stale
// numbers.
int refit_while_querying(int accel) {
  mallopt(M_MMAP_THRESHOLD, 64 * 1024);
  const Spheres a = placement(1), b = placement(2);
  const std::vector<sphray_ray> rays = some_rays();
  sphray_scene_args args = SPHRAY_SCENE_ARGS_INIT;
  args.accel = accel;
  sphray_scene* scene = nullptr;
  if (sphray_scene_create(a.cx.data(), a.cy.data(), a.cz.data(), a.r.data(), kSpheres, 0, &args,
                          &scene) != SPHRAY_OK)
    return 2;
  std::atomic<bool> done{false}, failed{false};
  std::vector<std::thread> readers;
  for (int t = 0; t < 2; ++t)
    readers.emplace_back([&] {
      while (!done.load(std::memory_order_relaxed))
        if (!query_once(scene, rays)) failed = true;
    });
  int status = 0;
  for (int i = 0; i < kRefits && status == 0; ++i) {
    const Spheres& s = i % 2 == 0 ? b : a;
    if (sphray_scene_refit(scene, s.cx.data(), s.cy.data(), s.cz.data(), s.r.data(), kSpheres, 0) !=
        SPHRAY_OK)
      status = 2;
  }
  done = true;
  for (std::thread& t : readers)
    t.join();
  if (status != 0) return status;
  if (failed) return 1;
  // kRefits is even: the last placement is a.
  sphray_scene* fresh = nullptr;
  if (sphray_scene_create(a.cx.data(), a.cy.data(), a.cz.data(), a.r.data(), kSpheres, 0, &args,
                          &fresh) != SPHRAY_OK)
    return 2;
  std::vector<sphray_hit> got(rays.size()), want(rays.size());
  std::vector<sphray_hit_surface> got_s(rays.size()), want_s(rays.size());
  sphray_intersect(scene, rays.data(), rays.size(), got.data(), nullptr);
  sphray_intersect(fresh, rays.data(), rays.size(), want.data(), nullptr);
  sphray_surface(scene, rays.data(), got.data(), rays.size(), got_s.data());
  sphray_surface(fresh, rays.data(), want.data(), rays.size(), want_s.data());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (got[i].id != want[i].id ||
        std::bit_cast<std::uint32_t>(got[i].t) != std::bit_cast<std::uint32_t>(want[i].t) ||
        std::bit_cast<std::uint32_t>(got_s[i].nx) != std::bit_cast<std::uint32_t>(want_s[i].nx))
      return 3;
  }
  sphray_scene_release(fresh);
  sphray_scene_release(scene);
  return 0;
}

void expect_child_passes(int accel) {
  const pid_t child = fork();
  ASSERT_NE(child, -1);
  if (child == 0) _exit(refit_while_querying(accel));
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: a query failed, 2: a refit failed, 3: the answers "
                                       "after the refits are not a new scene's";
}

TEST(CApiThreads, RefitWhileQueryingABruteForceSceneIsSafe) {
  expect_child_passes(SPHRAY_ACCEL_BRUTE);
}

// The tree was refitted in place already; its scene's spheres (which surface() reads) were not.
TEST(CApiThreads, RefitWhileQueryingABvhSceneIsSafe) {
  expect_child_passes(SPHRAY_ACCEL_BVH);
}

#endif

}  // namespace
