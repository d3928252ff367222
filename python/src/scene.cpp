#include "scene.hpp"

#include <mutex>
#include <optional>
#include <vector>

#include "arrays.hpp"
#include "interruption.hpp"
#include "ray_batches.hpp"
#include "results.hpp"
#include "sphray/render/renderer.hpp"

namespace sphray::python {
namespace {

// Whether a is float64 (or wider: longdouble), the dtypes that make a scene double when
// precision is None. Lists of Python floats come as float64 too.
bool wants_double(const py::array& a) {
  return a.dtype().kind() == 'f' && a.dtype().itemsize() >= 8;
}

// precision= as "double" or not; nullopt for None (the arrays' dtype decides).
std::optional<bool> double_asked(const py::handle& precision) {
  if (precision.is_none()) return std::nullopt;
  if (py::isinstance<py::str>(precision)) {
    const auto name = precision.cast<std::string>();
    if (name == "float" || name == "double") return name == "double";
  }
  throw py::value_error("precision: expected None, 'float' or 'double', got " +
                        std::string(py::repr(precision)));
}

}  // namespace

Scene::Scene(const py::handle& centers, const py::handle& radii, const std::string& accel,
             const py::handle& masks, const py::handle& precision)
    : scene_(make(centers, radii, accel, masks, precision)) {}

Scene::Scenes Scene::make(const py::handle& centers, const py::handle& radii,
                          const std::string& accel, const py::handle& masks,
                          const py::handle& precision) {
  const std::optional<bool> asked = double_asked(precision);
  // Converted once here (a list becomes its array), then read or copied by the scene.
  const py::array c = as_real_array("centers", centers);
  const py::array r = as_real_array("radii", radii);
  if (asked.value_or(wants_double(c) || wants_double(r)))
    return Scenes(std::in_place_type<SceneOf<double>>, c, r, accel, masks);
  return Scenes(std::in_place_type<SceneOf<float>>, c, r, accel, masks);
}

template <Scalar S>
SceneOf<S>::SceneOf(const py::array& centers, const py::array& radii, const std::string& accel,
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

template <Scalar S>
py::tuple SceneOf<S>::intersect(const py::handle& origins, const py::handle& directions,
                                const py::handle& tmin, const py::handle& tmax,
                                const py::handle& mask) const {
  const RayArguments<S> args(origins, directions, tmin, tmax, mask);
  const Vec3Rows<S>& o = args.origins;
  auto t = new_array<S>(o.leading_shape());
  auto ids = new_array<std::uint32_t>(o.leading_shape());
  S* t_out = t.mutable_data();
  std::uint32_t* id_out = ids.mutable_data();
  const RayBatch<S> rays = args.batch();
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    for_each_chunk(rays.size(), [&](std::size_t begin, std::size_t end) {
      std::vector<RayS> chunk(end - begin);
      std::vector<HitS> hits(end - begin);
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

template <Scalar S>
py::array SceneOf<S>::occluded(const py::handle& origins, const py::handle& directions,
                               const py::handle& tmin, const py::handle& tmax,
                               const py::handle& mask) const {
  const RayArguments<S> args(origins, directions, tmin, tmax, mask);
  const Vec3Rows<S>& o = args.origins;
  auto hit = new_array<bool>(o.leading_shape());
  bool* out = hit.mutable_data();
  const RayBatch<S> rays = args.batch();
  {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    // Through the stream call: on a tree, coherent rays go in packets.
    for_each_chunk(rays.size(), [&](std::size_t begin, std::size_t end) {
      std::vector<RayS> chunk(end - begin);
      for (std::size_t i = begin; i < end; ++i)
        chunk[i - begin] = rays[i];
      answer([&](const auto& spheres) {
        sphray::occluded(spheres, std::span<const RayS>(chunk),
                         std::span(out + begin, end - begin));
      });
    });
  }
  return hit;
}

template <Scalar S>
template <class Keep>
void SceneOf<S>::each_surface(const Vec3Rows<S>& o, const Vec3Rows<S>& d, const ScalarPerRow<S>& t,
                              const std::vector<std::uint32_t>& ids, const Keep& keep) const {
  py::gil_scoped_release release;
  std::shared_lock lock(mutex_);
  const BasicSphereView<S> view = spheres_.view();
  for_each_chunk(o.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      keep(i, sphray::surface(view, RayS{o[i], d[i]}, HitS{t[i], ids[i]}));
  });
}

template <Scalar S>
py::tuple SceneOf<S>::surface(const py::handle& origins, const py::handle& directions,
                              const py::handle& t, const py::handle& ids) const {
  const Vec3Rows<S> o("origins", origins);
  const Vec3Rows<S> d = directions_like(o, directions);
  const ScalarPerRow<S> hit_t("t", t, o.leading_shape());
  const std::vector<std::uint32_t> hit_ids = ids_per_row("ids", ids, o.leading_shape());
  auto points = new_array<S>(o.leading_shape(), {3});
  auto normals = new_array<S>(o.leading_shape(), {3});
  auto front = new_array<bool>(o.leading_shape());
  S* p_out = points.mutable_data();
  S* n_out = normals.mutable_data();
  bool* f_out = front.mutable_data();
  each_surface(o, d, hit_t, hit_ids, [&](std::size_t i, const SurfaceS& s) {
    for (int k = 0; k < 3; ++k) {
      p_out[3 * i + k] = s.point[k];
      n_out[3 * i + k] = s.normal[k];
    }
    f_out[i] = s.front_face;
  });
  return make_result(Result::surface, {points, normals, front});
}

template <Scalar S>
py::array SceneOf<S>::spawn(const py::handle& origins, const py::handle& directions,
                            const py::handle& t, const py::handle& ids,
                            const py::handle& new_directions) const {
  const Vec3Rows<S> o("origins", origins);
  const Vec3Rows<S> d = directions_like(o, directions);
  const Vec3Rows<S> next = directions_like(o, new_directions, "new_directions");
  const ScalarPerRow<S> hit_t("t", t, o.leading_shape());
  const std::vector<std::uint32_t> hit_ids = ids_per_row("ids", ids, o.leading_shape());
  auto spawned = new_array<S>(o.leading_shape(), {3});
  S* out = spawned.mutable_data();
  each_surface(o, d, hit_t, hit_ids, [&](std::size_t i, const SurfaceS& s) {
    const Vec p = sphray::offset_origin(s, next[i]);
    for (int k = 0; k < 3; ++k)
      out[3 * i + k] = p[k];
  });
  return spawned;
}

template <Scalar S>
void SceneOf<S>::trace(std::span<const RayS> rays, std::span<HitS> hits) const {
  answer([&](const auto& spheres) { sphray::intersect(spheres, rays, hits); });
}

template <Scalar S>
void SceneOf<S>::refit(const py::handle& centers, const py::handle& radii,
                       const py::handle& masks) {
  const py::array c = as_real_array("centers", centers);
  SphereArrays<S> next(c, as_real_array("radii", radii), masks);
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

template <Scalar S>
sphray::SphereSoA SceneOf<S>::copy_spheres() const {
  std::shared_lock lock(mutex_);
  const BasicSphereView<S> v = spheres_.view();
  const auto f = [](S x) { return static_cast<float>(x); };  // the renderer traces in float
  sphray::SphereSoA copy;
  copy.reserve(v.count);
  for (std::size_t i = 0; i < v.count; ++i)
    copy.add({f(v.cx[i]), f(v.cy[i]), f(v.cz[i])}, f(v.radius[i]));
  return copy;
}

// Every member defined here, for both precisions (queries.cpp instantiates its own members:
// a class may be explicitly instantiated once only).
template class SceneOf<float>;
template class SceneOf<double>;

}  // namespace sphray::python
