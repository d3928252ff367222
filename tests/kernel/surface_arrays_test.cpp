// surfaces() and offset_origins(), the array forms of surface() and offset_origin(): on every
// instruction set, every lane gets the one-hit functions' bits, for hits, misses, ids past the
// view, rays starting anywhere on their line (tmin -infinity), hits at a centre, NaN and
// infinite inputs, and every count from none to a few batches and a remainder.
#include <bit>
#include <limits>

#include "test_support.hpp"

namespace sphray {
namespace {

using detail::EntryTable;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// The same float, NaN included (the vector and scalar code make the same NaN here).
bool same(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

// Rays, their hits as arrays per quantity, and room for the surfaces and the next origins.
struct Lanes {
  std::vector<float> ox, oy, oz, dx, dy, dz, tmin, t;
  std::vector<std::uint32_t> id;
  std::vector<float> px, py, pz, nx, ny, nz, ex, ey, ez, next_x, next_y, next_z;
  std::unique_ptr<bool[]> front;
  std::size_t count = 0;

  void add(const Ray& ray, const Hit& hit) {
    ox.push_back(ray.origin.x), oy.push_back(ray.origin.y), oz.push_back(ray.origin.z);
    dx.push_back(ray.dir.x), dy.push_back(ray.dir.y), dz.push_back(ray.dir.z);
    tmin.push_back(ray.tmin), t.push_back(hit.t), id.push_back(hit.id);
    ++count;
  }
  void make_room() {
    for (auto* v : {&px, &py, &pz, &nx, &ny, &nz, &ex, &ey, &ez, &next_x, &next_y, &next_z})
      v->assign(count, -1.0f);
    front = std::make_unique<bool[]>(count + 1);
  }
  Ray ray(std::size_t i) const { return rays().at(i); }
  RayArrays rays() const {
    return {ox.data(), oy.data(),   oz.data(), dx.data(), dy.data(),
            dz.data(), tmin.data(), nullptr,   nullptr,   count};
  }
  HitArrays hits() { return {t.data(), id.data(), count}; }
  SurfaceArrays surfaces() {
    return {px.data(),   py.data(), pz.data(), nx.data(), ny.data(), nz.data(),
            front.get(), ex.data(), ey.data(), ez.data(), count};
  }
  VectorArrays dirs() const { return {dx.data(), dy.data(), dz.data(), count}; }
  VectorOutArrays next() { return {next_x.data(), next_y.data(), next_z.data(), count}; }
};

// A scene of spheres from radius 1e-3 to 1e3, one of radius 1e-30 (a hit at its centre has no
// direction from it), and rays that hit them, miss them, or carry a hit the scene cannot have.
struct Cases {
  SphereSoA spheres;
  Lanes lanes;
};

Cases make_cases(std::size_t rays, std::mt19937& rng) {
  Cases c;
  for (int i = 0; i < 40; ++i) {
    const float r = std::exp(test::uniform(rng, std::log(1e-3f), std::log(1e3f)));
    c.spheres.add(test::random_in_box(rng, 2e3f), r);
  }
  c.spheres.add({5.0f, 5.0f, 5.0f}, 1e-30f);
  const SphereView view = c.spheres.view();
  for (std::size_t i = 0; i < rays; ++i) {
    const std::uint32_t target = static_cast<std::uint32_t>(rng() % view.count);
    const Vec3 center{view.cx[target], view.cy[target], view.cz[target]};
    Ray ray{test::random_in_box(rng, 3e3f), test::random_direction(rng)};
    ray.dir = normalize(center - ray.origin) * test::uniform(rng, 0.5f, 2.0f);
    if (i % 7 == 1) ray.tmin = -kInf;                        // the near root of the line
    if (i % 7 == 2) ray.origin = center;                     // from inside
    if (i % 11 == 3) ray.dir = test::random_direction(rng);  // mostly a miss
    Hit hit = scalar::intersect(view, ray);
    switch (i % 13) {
      case 4:
        hit = {test::uniform(rng, 0.0f, 10.0f), static_cast<std::uint32_t>(view.count)};
        break;  // past the view
      case 5:
        hit = {kInf, kNoHit};
        break;
      case 6:
        hit = {kNaN, target};
        break;
      case 7:
        ray.origin.x = kNaN;
        break;
      case 8:
        hit = {1e30f, target};
        break;  // p - centre overflows: the normal faces the ray
      case 9:
        hit = {0.0f, static_cast<std::uint32_t>(view.count - 1)};
        ray.origin = {5, 5, 5};
        break;  // at the tiny sphere's centre
      default:
        break;
    }
    c.lanes.add(ray, hit);
  }
  c.lanes.make_room();
  return c;
}

void expect_surfaces(const Cases& c, std::size_t count, const std::string& where) {
  const SphereView view = c.spheres.view();
  const Lanes& l = c.lanes;
  for (std::size_t i = 0; i < count; ++i) {
    const Surface s = surface(view, l.ray(i), {l.t[i], l.id[i]});
    const bool agrees = same(l.px[i], s.point.x) && same(l.py[i], s.point.y) &&
                        same(l.pz[i], s.point.z) && same(l.nx[i], s.normal.x) &&
                        same(l.ny[i], s.normal.y) && same(l.nz[i], s.normal.z) &&
                        l.front[i] == s.front_face && same(l.ex[i], s.error.x) &&
                        same(l.ey[i], s.error.y) && same(l.ez[i], s.error.z);
    ASSERT_TRUE(agrees) << where << ", lane " << i << " of " << count << ": point " << l.px[i]
                        << " " << l.py[i] << " " << l.pz[i] << " against " << s.point.x << " "
                        << s.point.y << " " << s.point.z << ", normal " << l.nx[i] << " " << l.ny[i]
                        << " " << l.nz[i] << " against " << s.normal.x << " " << s.normal.y << " "
                        << s.normal.z << ", front " << l.front[i] << " against " << s.front_face;
  }
}

void expect_origins(const Cases& c, std::size_t count, const std::string& where) {
  Lanes& l = const_cast<Lanes&>(c.lanes);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 o = offset_origin(l.surfaces().at(i), l.dirs().at(i));
    ASSERT_TRUE(same(l.next_x[i], o.x) && same(l.next_y[i], o.y) && same(l.next_z[i], o.z))
        << where << ", lane " << i << " of " << count << ": " << l.next_x[i] << " " << l.next_y[i]
        << " " << l.next_z[i] << " against " << o.x << " " << o.y << " " << o.z;
  }
}

// Every count from 0 to three batches and some, so every remainder is a partial batch.
TEST(SurfaceArrays, EveryKernelGivesTheOneHitFunctionsBits) {
  std::mt19937 rng(71);
  Cases c = make_cases(2000, rng);
  std::size_t lanes_checked = 0;
  for (const EntryTable* k : test::runnable_kernels()) {
    for (std::size_t count : {0, 1, 2, 3, 5, 7, 8, 9, 15, 16, 17, 31, 33, 49, 64, 2000}) {
      Lanes& l = c.lanes;
      l.make_room();
      const std::string where = test::name_of(k) + ", count " + std::to_string(count);
      RayArrays rays = l.rays();
      HitArrays hits = l.hits();
      SurfaceArrays surfaces = l.surfaces();
      rays.count = hits.count = surfaces.count = count;
      k->surfaces(c.spheres.view(), rays, hits, surfaces);
      ASSERT_NO_FATAL_FAILURE(expect_surfaces(c, count, where));
      // The lane past the count untouched.
      if (count < l.count) {
        EXPECT_EQ(l.px[count], -1.0f) << where;
      }
      VectorArrays dirs = l.dirs();
      VectorOutArrays next = l.next();
      dirs.count = next.count = count;
      k->offset_origins(surfaces, dirs, next);
      ASSERT_NO_FATAL_FAILURE(expect_origins(c, count, where));
      if (count < l.count) {
        EXPECT_EQ(l.next_x[count], -1.0f) << where;
      }
      lanes_checked += count;
    }
  }
  EXPECT_GE(lanes_checked, 2000u * test::runnable_kernels().size());
}

// The cases above take every branch: hits and misses, both faces, a hit without direction.
TEST(SurfaceArrays, TheCasesCoverEveryKindOfLane) {
  std::mt19937 rng(71);
  const Cases c = make_cases(2000, rng);
  const SphereView view = c.spheres.view();
  int found = 0, missed = 0, front = 0, back = 0, facing_ray = 0;
  for (std::size_t i = 0; i < c.lanes.count; ++i) {
    const Ray ray = c.lanes.ray(i);
    const Hit hit{c.lanes.t[i], c.lanes.id[i]};
    const Surface s = surface(view, ray, hit);
    if (!hit.found() || hit.id >= view.count) {
      ++missed;
      continue;
    }
    ++found;
    (s.front_face ? front : back) += 1;
    const Vec3 toward = -ray.dir / length(ray.dir);
    if (std::fabs(dot(s.normal, toward) - 1.0f) < 1e-6f) ++facing_ray;
  }
  EXPECT_GT(found, 1000);
  EXPECT_GT(missed, 200);
  EXPECT_GT(front, 500);
  EXPECT_GT(back, 100);
  EXPECT_GT(facing_ray, 10);  // no direction from the centre: the normal faces the ray
}

TEST(SurfaceArrays, ThePublicCallsCheckTheirArguments) {
  std::mt19937 rng(5);
  Cases c = make_cases(40, rng);
  Lanes& l = c.lanes;
  const SphereView view = c.spheres.view();
  surfaces(view, l.rays(), l.hits(), l.surfaces());
  ASSERT_NO_FATAL_FAILURE(expect_surfaces(c, l.count, "sphray::surfaces"));
  offset_origins(l.surfaces(), l.dirs(), l.next());
  ASSERT_NO_FATAL_FAILURE(expect_origins(c, l.count, "sphray::offset_origins"));

  SurfaceArrays short_out = l.surfaces();
  short_out.count -= 1;
  EXPECT_THROW(surfaces(view, l.rays(), l.hits(), short_out), std::length_error);
  SurfaceArrays no_front = l.surfaces();
  no_front.front_face = nullptr;
  EXPECT_THROW(surfaces(view, l.rays(), l.hits(), no_front), std::invalid_argument);
  HitArrays no_ids = l.hits();
  no_ids.id = nullptr;
  EXPECT_THROW(surfaces(view, l.rays(), no_ids, l.surfaces()), std::invalid_argument);
  VectorOutArrays short_next = l.next();
  short_next.count = 0;
  EXPECT_THROW(offset_origins(l.surfaces(), l.dirs(), short_next), std::length_error);
  VectorArrays no_dirs = l.dirs();
  no_dirs.y = nullptr;
  EXPECT_THROW(offset_origins(l.surfaces(), no_dirs, l.next()), std::invalid_argument);
  // Nothing to do: no array is read, so none need be given.
  EXPECT_NO_THROW(surfaces(view, RayArrays{}, HitArrays{}, SurfaceArrays{}));
  EXPECT_NO_THROW(offset_origins(SurfaceArrays{}, VectorArrays{}, VectorOutArrays{}));
}

}  // namespace
}  // namespace sphray
