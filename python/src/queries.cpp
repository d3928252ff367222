// sphray.Scene's queries beyond the closest hit (docs/queries.md): every crossing and their
// count along rays, and the point queries. Like the closest hit: the GIL released, large
// batches in chunks over oneTBB's workers, the reader lock against refit.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <tbb/parallel_sort.h>

#include "arrays.hpp"
#include "interruption.hpp"
#include "ray_batches.hpp"
#include "results.hpp"
#include "scene.hpp"
#include "storage/morton_order.hpp"

namespace sphray::python {

// More slots per ray than any real use and small enough that rays * slots cannot overflow.
constexpr std::size_t kMaxHitsPerRay = 1 << 20;

template <Scalar S>
py::tuple SceneOf<S>::intersect_all(const py::handle& origins, const py::handle& directions,
                                    std::size_t max_hits, const py::handle& tmin,
                                    const py::handle& tmax, const py::handle& mask) const {
  return crossings(origins, directions, max_hits, tmin, tmax, mask, Crossings::all);
}

template <Scalar S>
py::tuple SceneOf<S>::intersect_nearest(const py::handle& origins, const py::handle& directions,
                                        std::size_t k, const py::handle& tmin,
                                        const py::handle& tmax, const py::handle& mask) const {
  return crossings(origins, directions, k, tmin, tmax, mask, Crossings::nearest);
}

template <Scalar S>
py::tuple SceneOf<S>::crossings(const py::handle& origins, const py::handle& directions,
                                std::size_t max_hits, const py::handle& tmin,
                                const py::handle& tmax, const py::handle& mask,
                                Crossings which) const {
  if (max_hits > kMaxHitsPerRay) {
    throw py::value_error("max_hits: expected 0 to " + std::to_string(kMaxHitsPerRay) + ", got " +
                          std::to_string(max_hits));
  }
  const RayArguments<S> args(origins, directions, tmin, tmax, mask);
  const Vec3Rows<S>& o = args.origins;
  const auto slots = static_cast<py::ssize_t>(max_hits);
  auto t = new_array<S>(o.leading_shape(), {slots});
  auto ids = new_array<std::uint32_t>(o.leading_shape(), {slots});
  auto exits = new_array<bool>(o.leading_shape(), {slots});
  auto counts = new_array<std::uint64_t>(o.leading_shape());
  S* t_out = t.mutable_data();
  std::uint32_t* id_out = ids.mutable_data();
  bool* exit_out = exits.mutable_data();
  std::uint64_t* count_out = counts.mutable_data();
  const RayBatch<S> rays = args.batch();
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    for_each_chunk(rays.size(), [&](std::size_t begin, std::size_t end) {
      std::vector<HitS> hits(max_hits);
      auto flags = std::make_unique<bool[]>(max_hits + 1);
      const std::span<bool> exit_span(flags.get(), max_hits);
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t n = answer([&](const auto& spheres) {
          return which == Crossings::all
                     ? sphray::intersect_all(spheres, rays[i], hits, exit_span)
                     : sphray::intersect_nearest(spheres, rays[i], hits, exit_span);
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
  return make_result(which == Crossings::all ? Result::crossings : Result::nearest_crossings,
                     {t, ids, exits, counts});
}

template <Scalar S>
py::array SceneOf<S>::count_hits(const py::handle& origins, const py::handle& directions,
                                 const py::handle& tmin, const py::handle& tmax,
                                 const py::handle& mask) const {
  const RayArguments<S> args(origins, directions, tmin, tmax, mask);
  const Vec3Rows<S>& o = args.origins;
  auto counts = new_array<std::uint64_t>(o.leading_shape());
  std::uint64_t* out = counts.mutable_data();
  const RayBatch<S> rays = args.batch();
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

template <Scalar S>
py::tuple SceneOf<S>::nearest(const py::handle& points, double max_distance) const {
  const Vec3Rows<S> p("points", points);
  const auto limit = static_cast<S>(max_distance);
  auto ids = new_array<std::uint32_t>(p.leading_shape());
  auto distances = new_array<S>(p.leading_shape());
  auto surface_points = new_array<S>(p.leading_shape(), {3});
  std::uint32_t* id_out = ids.mutable_data();
  S* d_out = distances.mutable_data();
  S* p_out = surface_points.mutable_data();
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    for_each_chunk(p.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const BasicNearest<S> n =
            answer([&](const auto& spheres) { return sphray::nearest(spheres, p[i], limit); });
        id_out[i] = n.id;
        d_out[i] = n.distance;
        for (int k = 0; k < 3; ++k)
          p_out[3 * i + static_cast<std::size_t>(k)] = n.point[k];
      }
    });
  }
  return make_result(Result::nearest, {ids, distances, surface_points});
}

template <Scalar S>
py::array SceneOf<S>::inside(const py::handle& points) const {
  const Vec3Rows<S> p("points", points);
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

template <Scalar S>
py::array SceneOf<S>::overlapping(const py::handle& centre, double radius) const {
  // Refused like every other array argument: TypeError for a dtype that is not real (complex
  // included, whose imaginary part a cast would drop), ValueError for the shape.
  const py::array a = as_real_array("centre", centre);
  if (a.ndim() != 1 || a.shape(0) != 3)
    throw py::value_error("centre: expected the shape (3,), got " + shape_text(a));
  const auto c = converted<S, py::array::c_style>("centre", a);
  const Vec at{c.at(0), c.at(1), c.at(2)};
  const auto reach = static_cast<S>(radius);
  std::vector<std::uint32_t> ids;
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    auto query = [&](std::span<std::uint32_t> out) {
      return answer(
          [&](const auto& spheres) { return sphray::overlapping(spheres, at, reach, out); });
    };
    // Counted first, then listed: the answer's size is not known before.
    ids.resize(query({}));
    query(ids);
  }
  auto out = new_array<std::uint32_t>({static_cast<py::ssize_t>(ids.size())});
  std::copy(ids.begin(), ids.end(), out.mutable_data());
  return out;
}

namespace {

// Ids per ball before a second, exact query is needed: most balls of a simulation's broad phase
// overlap a handful of spheres.
constexpr std::size_t kIdsGuess = 32;

// The ids of the spheres a query(out) finds, appended to ids: one query when they fit the
// guess, else a second with room for all.
template <class Query>
std::size_t append_ids(std::vector<std::uint32_t>& ids, const Query& query) {
  const std::size_t at = ids.size();
  ids.resize(at + kIdsGuess);
  const std::size_t total = query(std::span<std::uint32_t>(ids.data() + at, kIdsGuess));
  ids.resize(at + total);
  if (total > kIdsGuess) query(std::span<std::uint32_t>(ids.data() + at, total));
  return total;
}

// The balls 0..n-1 in Morton order of their centres (centre(i) -> Vec3): neighbouring queries
// then walk the same nodes of the tree, which stay in the caches, where queries in the caller's
// order (random, for particles) wait on memory at nearly every node. The order changes no
// answer.
template <class Centre>
std::vector<std::uint32_t> spatial_order(std::size_t n, const Centre& centre) {
  // Morton codes are taken in float: a double centre rounded to float changes only the order
  // (one beyond float's range counts as not finite, sorted with the NaNs), never an answer.
  const auto in_float = [&](std::size_t i) {
    const auto c = centre(i);
    return Vec3{static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
  };
  return detail::morton_order(n, in_float,
                              [](auto begin, auto end) { tbb::parallel_sort(begin, end); });
}

// Lists made in the order `order` (lists[k] the ids of its positions in chunk k, counts[i] the
// number of ball i) to the sparse row layout in the balls' own order: offsets[0..n] and ids.
void scatter_lists(const std::vector<std::vector<std::uint32_t>>& lists,
                   const std::vector<std::uint32_t>& order, std::int64_t* offsets,
                   std::uint32_t* ids) {
  const std::size_t n = order.size();
  std::int64_t sum = 0;  // offsets[1..n] hold the counts: shift them into running sums
  for (std::size_t i = 0; i <= n; ++i) {
    const std::int64_t count = i < n ? offsets[i + 1] : 0;
    offsets[i] = sum;
    sum += count;
  }
  for (std::size_t k = 0; k < lists.size(); ++k) {
    const std::uint32_t* id = lists[k].data();
    for (std::size_t s = k * kChunkRays; s < std::min(n, (k + 1) * kChunkRays); ++s) {
      const std::uint32_t i = order[s];
      for (std::int64_t row = offsets[i]; row < offsets[i + 1]; ++row)
        ids[row] = *id++;
    }
  }
}

}  // namespace

template <Scalar S>
py::tuple SceneOf<S>::overlaps(const py::handle& centers, const py::handle& radii) const {
  const Vec3Rows<S> c("centers", centers);
  const ScalarPerRow<S> r("radii", radii, c.leading_shape());
  const std::size_t n = c.size();
  // Morton order numbers the balls in 32 bits.
  if (n > std::size_t{0xffffffff})
    throw py::value_error("centers: expected at most 2**32 - 1 balls, got " + std::to_string(n));
  auto offsets = new_array<std::int64_t>({static_cast<py::ssize_t>(n + 1)});
  std::int64_t* counts = offsets.mutable_data() + 1;
  std::vector<std::uint32_t> order;
  // lists[k]: the ids found for the balls of chunk k of the order, ball after ball.
  std::vector<std::vector<std::uint32_t>> lists((n + kChunkRays - 1) / kChunkRays);
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    order = spatial_order(n, [&](std::size_t i) { return c[i]; });
    for_each_chunk(n, [&](std::size_t begin, std::size_t end) {
      std::vector<std::uint32_t>& ids = lists[begin / kChunkRays];
      for (std::size_t s = begin; s < end; ++s) {
        const std::uint32_t i = order[s];
        counts[i] = static_cast<std::int64_t>(append_ids(ids, [&](std::span<std::uint32_t> out) {
          return answer(
              [&](const auto& spheres) { return sphray::overlapping(spheres, c[i], r[i], out); });
        }));
      }
    });
  }
  std::int64_t total = 0;
  for (const auto& list : lists)
    total += static_cast<std::int64_t>(list.size());
  auto ids = new_array<std::uint32_t>({static_cast<py::ssize_t>(total)});
  scatter_lists(lists, order, offsets.mutable_data(), ids.mutable_data());
  return make_result(Result::overlaps, {offsets, ids});
}

template <Scalar S>
py::array SceneOf<S>::overlapping_pairs() const {
  std::vector<std::uint64_t> keys;  // first << 32 | second: sorted, by first then second
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    std::optional<Tree> own;  // a scene without a tree (accel='brute') gets one here
    Interruption interruption;
    const Tree& tree = bvh_ ? *bvh_ : own.emplace(spheres_.view(), BvhBuildOptions{}, [&](double) {
      interruption.check();
      return true;
    });
    // Shares of the tree's leaves of about kChunkRays spheres, each into a list of its own.
    const std::size_t parts = std::max<std::size_t>(1, size() / kChunkRays);
    std::vector<std::vector<IdPair>> found(parts);
    for_each_piece(parts, size() >= kParallelFromRays, [&](std::size_t part) {
      sphray::overlapping_pairs(tree, found[part], part, parts);
    });
    std::vector<std::size_t> at(parts + 1, 0);
    for (std::size_t part = 0; part < parts; ++part)
      at[part + 1] = at[part] + found[part].size();
    keys.resize(at[parts]);
    for_each_piece(parts, size() >= kParallelFromRays, [&](std::size_t part) {
      std::uint64_t* key = keys.data() + at[part];
      for (const IdPair pair : found[part])
        *key++ = std::uint64_t{pair.first} << 32 | pair.second;
      std::vector<IdPair>().swap(found[part]);
    });
    tbb::parallel_sort(keys.begin(), keys.end());
  }
  auto pairs = new_array<std::uint32_t>({static_cast<py::ssize_t>(keys.size())}, {2});
  std::uint32_t* out = pairs.mutable_data();
  for (const std::uint64_t key : keys) {
    *out++ = static_cast<std::uint32_t>(key >> 32);
    *out++ = static_cast<std::uint32_t>(key);
  }
  return pairs;
}

// The members defined here, for both precisions. Member by member: the class itself is
// instantiated in scene.cpp, and a class may be explicitly instantiated only once.
#define SPHRAY_SCENE_QUERIES(S)                                                                   \
  template py::tuple SceneOf<S>::crossings(const py::handle&, const py::handle&, std::size_t,     \
                                           const py::handle&, const py::handle&,                  \
                                           const py::handle&, Crossings) const;                   \
  template py::tuple SceneOf<S>::intersect_all(const py::handle&, const py::handle&, std::size_t, \
                                               const py::handle&, const py::handle&,              \
                                               const py::handle&) const;                          \
  template py::tuple SceneOf<S>::intersect_nearest(const py::handle&, const py::handle&,          \
                                                   std::size_t, const py::handle&,                \
                                                   const py::handle&, const py::handle&) const;   \
  template py::array SceneOf<S>::count_hits(const py::handle&, const py::handle&,                 \
                                            const py::handle&, const py::handle&,                 \
                                            const py::handle&) const;                             \
  template py::tuple SceneOf<S>::nearest(const py::handle&, double) const;                        \
  template py::array SceneOf<S>::inside(const py::handle&) const;                                 \
  template py::array SceneOf<S>::overlapping(const py::handle&, double) const;                    \
  template py::tuple SceneOf<S>::overlaps(const py::handle&, const py::handle&) const;            \
  template py::array SceneOf<S>::overlapping_pairs() const;
SPHRAY_SCENE_QUERIES(float)
SPHRAY_SCENE_QUERIES(double)
#undef SPHRAY_SCENE_QUERIES

}  // namespace sphray::python
