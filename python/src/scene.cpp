#include "scene.hpp"

#include <mutex>
#include <vector>

#include "arrays.hpp"
#include "interruption.hpp"
#include "ray_batches.hpp"
#include "results.hpp"
#include "sphray/render/renderer.hpp"

namespace sphray::python {

Scene::Scene(const py::handle& centers, const py::handle& radii, const std::string& accel,
             const py::handle& masks)
    : spheres_(centers, radii, masks) {
  using render::Accel;
  const std::optional<Accel> how = render::parse_accel(accel);
  if (!how) throw py::value_error("accel: expected 'auto', 'bvh' or 'brute', got '" + accel + "'");
  if (how == Accel::bvh || (how == Accel::automatic && spheres_.size() >= kBvhFromSpheres)) {
    py::gil_scoped_release release;
    // A build of millions of spheres takes seconds: Ctrl-C stops it (interruption.hpp).
    Interruption interruption;
    bvh_.emplace(spheres_.view(), BvhBuildOptions{}, [&](double) {
      interruption.check();
      return true;
    });
  }
}

py::tuple Scene::intersect(const py::handle& origins, const py::handle& directions,
                           const py::handle& tmin, const py::handle& tmax,
                           const py::handle& mask) const {
  const RayArguments args(origins, directions, tmin, tmax, mask);
  const Vec3Rows& o = args.origins;
  auto t = new_array<float>(o.leading_shape());
  auto ids = new_array<std::uint32_t>(o.leading_shape());
  float* t_out = t.mutable_data();
  std::uint32_t* id_out = ids.mutable_data();
  const RayBatch rays = args.batch();
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    for_each_chunk(rays.size(), [&](std::size_t begin, std::size_t end) {
      std::vector<Ray> chunk(end - begin);
      std::vector<Hit> hits(end - begin);
      for (std::size_t i = begin; i < end; ++i)
        chunk[i - begin] = rays[i];
      trace(chunk, hits);
      for (std::size_t i = begin; i < end; ++i) {
        t_out[i] = hits[i - begin].t;
        id_out[i] = hits[i - begin].id;
      }
    });
  }
  return make_result(Result::hits, {t, ids});
}

py::array Scene::occluded(const py::handle& origins, const py::handle& directions,
                          const py::handle& tmin, const py::handle& tmax,
                          const py::handle& mask) const {
  const RayArguments args(origins, directions, tmin, tmax, mask);
  const Vec3Rows& o = args.origins;
  auto hit = new_array<bool>(o.leading_shape());
  bool* out = hit.mutable_data();
  const RayBatch rays = args.batch();
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    // Through the stream call: on a tree, coherent rays go in packets.
    for_each_chunk(rays.size(), [&](std::size_t begin, std::size_t end) {
      std::vector<Ray> chunk(end - begin);
      for (std::size_t i = begin; i < end; ++i)
        chunk[i - begin] = rays[i];
      answer([&](const auto& spheres) {
        sphray::occluded(spheres, std::span<const Ray>(chunk), std::span(out + begin, end - begin));
      });
    });
  }
  return hit;
}

template <class Keep>
void Scene::each_surface(const Vec3Rows& o, const Vec3Rows& d, const FloatPerRow& t,
                         const std::vector<std::uint32_t>& ids, const Keep& keep) const {
  py::gil_scoped_release release;
  std::shared_lock lock(mutex_);
  const SphereView view = spheres_.view();
  for_each_chunk(o.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      keep(i, sphray::surface(view, Ray{o[i], d[i]}, Hit{t[i], ids[i]}));
  });
}

py::tuple Scene::surface(const py::handle& origins, const py::handle& directions,
                         const py::handle& t, const py::handle& ids) const {
  const Vec3Rows o("origins", origins);
  const Vec3Rows d = directions_like(o, directions);
  const FloatPerRow hit_t("t", t, o.leading_shape());
  const std::vector<std::uint32_t> hit_ids = ids_per_row("ids", ids, o.leading_shape());
  auto points = new_array<float>(o.leading_shape(), {3});
  auto normals = new_array<float>(o.leading_shape(), {3});
  auto front = new_array<bool>(o.leading_shape());
  float* p_out = points.mutable_data();
  float* n_out = normals.mutable_data();
  bool* f_out = front.mutable_data();
  each_surface(o, d, hit_t, hit_ids, [&](std::size_t i, const Surface& s) {
    for (int k = 0; k < 3; ++k) {
      p_out[3 * i + k] = s.point[k];
      n_out[3 * i + k] = s.normal[k];
    }
    f_out[i] = s.front_face;
  });
  return make_result(Result::surface, {points, normals, front});
}

py::array Scene::spawn(const py::handle& origins, const py::handle& directions, const py::handle& t,
                       const py::handle& ids, const py::handle& new_directions) const {
  const Vec3Rows o("origins", origins);
  const Vec3Rows d = directions_like(o, directions);
  const Vec3Rows next = directions_like(o, new_directions, "new_directions");
  const FloatPerRow hit_t("t", t, o.leading_shape());
  const std::vector<std::uint32_t> hit_ids = ids_per_row("ids", ids, o.leading_shape());
  auto spawned = new_array<float>(o.leading_shape(), {3});
  float* out = spawned.mutable_data();
  each_surface(o, d, hit_t, hit_ids, [&](std::size_t i, const Surface& s) {
    const Vec3 p = sphray::offset_origin(s, next[i]);
    for (int k = 0; k < 3; ++k)
      out[3 * i + k] = p[k];
  });
  return spawned;
}

void Scene::trace(std::span<const Ray> rays, std::span<Hit> hits) const {
  answer([&](const auto& spheres) { sphray::intersect(spheres, rays, hits); });
}

void Scene::refit(const py::handle& centers, const py::handle& radii, const py::handle& masks) {
  SphereArrays next(centers, radii, masks);
  if (next.size() != spheres_.size()) {
    throw py::value_error("refit: expected the scene's " + std::to_string(spheres_.size()) +
                          " spheres, got centers " + shape_text(next.centers()));
  }
  // No masks given: the spheres keep theirs (only reads of spheres_, safe beside queries).
  if (masks.is_none()) next.copy_masks_from(spheres_);
  std::unique_lock lock(mutex_, std::defer_lock);
  {
    // No thread waits for the lock while it holds the GIL: queries release the GIL before they
    // take the lock (they may take the GIL back for a moment while they hold it, to answer a
    // Ctrl-C), and so does this wait; neither can hold up the other for ever.
    py::gil_scoped_release release;
    lock.lock();
    if (bvh_) bvh_->refit(next.view());
  }
  spheres_ = std::move(next);  // the old arrays are released with the GIL held
}

sphray::SphereSoA Scene::copy_spheres() const {
  std::shared_lock lock(mutex_);
  const SphereView v = spheres_.view();
  sphray::SphereSoA copy;
  copy.reserve(v.count);
  for (std::size_t i = 0; i < v.count; ++i)
    copy.add({v.cx[i], v.cy[i], v.cz[i]}, v.radius[i]);
  return copy;
}

}  // namespace sphray::python
