// sphray.Scene's queries beyond the closest hit (docs/queries.md): every crossing and their
// count along rays, and the point queries. Like the closest hit: the GIL released, large
// batches in chunks over oneTBB's workers, the reader lock against refit.
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <vector>

#include "arrays.hpp"
#include "ray_batches.hpp"
#include "scene.hpp"

namespace sphray::python {

// More slots per ray than any real use and small enough that rays * slots cannot overflow.
constexpr std::size_t kMaxHitsPerRay = 1 << 20;

py::tuple Scene::intersect_all(const py::handle& origins, const py::handle& directions,
                               std::size_t max_hits, const py::handle& tmin, const py::handle& tmax,
                               const py::handle& mask) const {
  if (max_hits > kMaxHitsPerRay) {
    throw py::value_error("max_hits: expected 0 to " + std::to_string(kMaxHitsPerRay) + ", got " +
                          std::to_string(max_hits));
  }
  const RayArguments args(origins, directions, tmin, tmax, mask);
  const Vec3Rows& o = args.origins;
  const auto slots = static_cast<py::ssize_t>(max_hits);
  auto t = new_array<float>(o.leading_shape(), {slots});
  auto ids = new_array<std::uint32_t>(o.leading_shape(), {slots});
  auto exits = new_array<bool>(o.leading_shape(), {slots});
  auto counts = new_array<std::uint64_t>(o.leading_shape());
  float* t_out = t.mutable_data();
  std::uint32_t* id_out = ids.mutable_data();
  bool* exit_out = exits.mutable_data();
  std::uint64_t* count_out = counts.mutable_data();
  const RayBatch rays = args.batch();
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    for_each_chunk(rays.size(), [&](std::size_t begin, std::size_t end) {
      std::vector<Hit> hits(max_hits);
      auto flags = std::make_unique<bool[]>(max_hits + 1);
      const std::span<bool> exit_span(flags.get(), max_hits);
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t n = answer([&](const auto& spheres) {
          return sphray::intersect_all(spheres, rays[i], hits, exit_span);
        });
        count_out[i] = n;
        for (std::size_t k = 0; k < max_hits; ++k) {
          const bool used = k < n;
          t_out[i * max_hits + k] = used ? hits[k].t : NAN;
          id_out[i * max_hits + k] = used ? hits[k].id : kNoHit;
          exit_out[i * max_hits + k] = used && flags[k];
        }
      }
    });
  }
  return py::make_tuple(t, ids, exits, counts);
}

py::array Scene::count_hits(const py::handle& origins, const py::handle& directions,
                            const py::handle& tmin, const py::handle& tmax,
                            const py::handle& mask) const {
  const RayArguments args(origins, directions, tmin, tmax, mask);
  const Vec3Rows& o = args.origins;
  auto counts = new_array<std::uint64_t>(o.leading_shape());
  std::uint64_t* out = counts.mutable_data();
  const RayBatch rays = args.batch();
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    for_each_chunk(rays.size(), [&](std::size_t begin, std::size_t end) {
      answer([&](const auto& spheres) {
        for (std::size_t i = begin; i < end; ++i)
          out[i] = sphray::count_hits(spheres, rays[i]);
      });
    });
  }
  return counts;
}

py::tuple Scene::nearest(const py::handle& points, float max_distance) const {
  const Vec3Rows p("points", points);
  auto ids = new_array<std::uint32_t>(p.leading_shape());
  auto distances = new_array<float>(p.leading_shape());
  auto surface_points = new_array<float>(p.leading_shape(), {3});
  std::uint32_t* id_out = ids.mutable_data();
  float* d_out = distances.mutable_data();
  float* p_out = surface_points.mutable_data();
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    for_each_chunk(p.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const Nearest n = answer(
            [&](const auto& spheres) { return sphray::nearest(spheres, p[i], max_distance); });
        id_out[i] = n.id;
        d_out[i] = n.distance;
        for (int k = 0; k < 3; ++k)
          p_out[3 * i + static_cast<std::size_t>(k)] = n.point[k];
      }
    });
  }
  return py::make_tuple(ids, distances, surface_points);
}

py::array Scene::inside(const py::handle& points) const {
  const Vec3Rows p("points", points);
  auto inside = new_array<bool>(p.leading_shape());
  bool* out = inside.mutable_data();
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    for_each_chunk(p.size(), [&](std::size_t begin, std::size_t end) {
      answer([&](const auto& spheres) {
        for (std::size_t i = begin; i < end; ++i)
          out[i] = sphray::inside(spheres, p[i]);
      });
    });
  }
  return inside;
}

py::array Scene::overlapping(const py::handle& centre, float radius) const {
  // Refused like every other array argument: TypeError for a dtype that is not real (complex
  // included, whose imaginary part a cast would drop), ValueError for the shape.
  const py::array a = as_real_array("centre", centre);
  if (a.ndim() != 1 || a.shape(0) != 3)
    throw py::value_error("centre: expected the shape (3,), got " + shape_text(a));
  const auto c = converted<float, py::array::c_style>("centre", a);
  const Vec3 at{c.at(0), c.at(1), c.at(2)};
  std::vector<std::uint32_t> ids;
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    auto query = [&](std::span<std::uint32_t> out) {
      return answer(
          [&](const auto& spheres) { return sphray::overlapping(spheres, at, radius, out); });
    };
    // Counted first, then listed: the answer's size is not known before.
    ids.resize(query({}));
    query(ids);
  }
  auto out = new_array<std::uint32_t>({static_cast<py::ssize_t>(ids.size())});
  std::copy(ids.begin(), ids.end(), out.mutable_data());
  return out;
}

}  // namespace sphray::python
