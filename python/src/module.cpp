// The sphray Python module: the bindings and their docstrings. The work is in scene.cpp
// (queries), sphere_arrays.cpp and arrays.cpp (reading numpy), camera.cpp (the renderer).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>

#include <cmath>
#include <string>
#include <unordered_map>
#include <vector>

#include "camera.hpp"
#include "interruption.hpp"
#include "particles_load.hpp"
#include "results.hpp"
#include "scene.hpp"
#include "sphray/sphray.hpp"

namespace py = pybind11;
using namespace pybind11::literals;
using sphray::python::RenderRequest;
using sphray::python::Scene;

namespace {

constexpr const char* kModuleDoc = R"doc(Fast, exact ray/sphere intersection on numpy arrays.

    >>> import numpy as np, sphray
    >>> scene = sphray.Scene(centers, radii)            # (N, 3) and (N,)
    >>> t, ids = scene.intersect(origins, directions)   # (M, 3) each -> (M,), (M,)
    >>> hit = scene.occluded(origins, directions)       # (M,) bool
    >>> points, normals, front = scene.surface(origins, directions, t, ids)
    >>> hits = scene.intersect(origins, directions)     # or by name: hits.t, hits.ids

The results of more than one array are named tuples (Hits, Surface, Crossings, Nearest,
Overlaps, Rays): they unpack as tuples and name their fields.

Results are exact to the kernel's contract (the C++ library's docs/kernel.md): a ray hits a
sphere at t when tmin < t < tmax, the closest hit wins, equal t goes to the lower id, a miss
has id NO_HIT and t = tmax, and NaN or infinite rays and spheres never hit. Queries release
the GIL and spread large batches over all cores.

The instruction set is chosen once per process from the CPU; the environment variable
SPHRAY_ISA (scalar, sse4.2, avx2, avx512, neon), set before the first query, forces one.
Every instruction set returns the same bits.)doc";

constexpr const char* kSceneDoc = R"doc(Spheres to trace rays against.

Scene(centers, radii, accel="auto", masks=None, precision=None)

centers: (N, 3) array of sphere centres; radii: (N,) array. Any real dtype. Sphere i has id
i. A sphere with radius <= 0 or a NaN or infinite value is never hit.

precision: None, "float" or "double". None: a double scene when centers or radii are
float64 (numpy's default, and lists of Python floats), else float (float32, float16,
integers). A double scene runs the double kernel: it reads float64 arrays (spheres, rays,
bounds, points) as they are, converts other dtypes to float64, and returns float64 where a
float scene returns float32. scene.precision says which. Rendering is float: render() rounds
a double scene's spheres to float.

masks: None, or (N,) integers in [0, 2**32 - 1] (copied as uint32). The ray queries take a
mask= keyword (an integer, numpy's included, or one per ray; default every bit): a ray sees
sphere i only if masks[i] & mask != 0. The point queries see every sphere.

accel: "auto" builds a bounding volume hierarchy (BVH) from 128 spheres on and traces
small scenes by brute force; "bvh" and "brute" force one or the other. Both return the
same results, bit for bit.

No copy is made of arrays of the scene's dtype (float32, or float64 for double) that the
kernel can read as they are: radii contiguous, centers with contiguous columns (Fortran
order, e.g. np.asfortranarray(c, np.float32) or the transpose of a (3, N) array). A
C-ordered (N, 3) array is copied once into that layout. The `centers` and `radii` attributes are read-only views of the arrays the scene
reads; while a scene reads your arrays in place, write to them only between queries and
call refit() afterwards (the BVH keeps its own copy of the spheres and sees changes only
then).)doc";

constexpr const char* kInitDoc =
    R"doc(init(self, centers, radii, accel="auto", masks=None, precision=None)
--

Spheres from centers (N, 3) and radii (N,), and optionally one uint32 mask each, in float or
double (precision; None: double when centers or radii are float64): see help(sphray.Scene). Raises RuntimeError on a scene already initialised.)doc";

constexpr const char* kIntersectDoc =
    R"doc(intersect(self, origins, directions, tmin=0.0, tmax=math.inf, mask=0xffffffff)
--

Closest hit of each ray: Hits(t, ids), a named tuple (t, ids = scene.intersect(...) unpacks it).

origins, directions: (M, 3) arrays (or (..., 3): the results then have shape (...)). Directions
need not be unit length: t is measured in units of the direction. tmin, tmax: scalars or arrays
of shape (M,); a hit needs tmin < t < tmax.

hits.t, float32 (M,) (float64 for a double scene), and hits.ids, uint32 (M,): on a miss ids[i] == NO_HIT and
t[i] == tmax. Equal t on two spheres: the lower id. A ray starting inside a sphere hits its
far side. A ray with a NaN or infinite component, a zero direction, a NaN bound or
tmin >= tmax misses.)doc";

constexpr const char* kOccludedDoc =
    R"doc(occluded(self, origins, directions, tmin=0.0, tmax=math.inf, mask=0xffffffff)
--

Whether each ray hits any sphere in (tmin, tmax).

The shadow-ray query: the same rays and rules as intersect(), a bool array of shape (M,),
stopping at the first hit found.)doc";

constexpr const char* kSurfaceDoc =
    R"doc(surface(self, origins, directions, t, ids)
--

Where each ray meets its hit: Surface(points, normals, front_face), a named tuple.

t and ids as intersect() returned them. points: float32 (M, 3) (float64 for a double scene),
on the sphere (re-projected from the ray's t); normals: the same dtype (M, 3), the outward unit
normals; front_face: bool (M,),
True where the ray arrived from outside. For a miss (ids == NO_HIT, or an id of no sphere):
the point origin + t * direction, a zero normal and front_face False.)doc";

constexpr const char* kSpawnDoc =
    R"doc(spawn(self, origins, directions, t, ids, new_directions)
--

Where rays leaving each hit towards new_directions start: the hit point moved along the normal,
to new_directions' side, just past the point's computed rounding error (sphray.spawn() in C++,
docs/kernel.md, "Leaving a surface"). A ray from there with direction new_directions never meets
the same sphere again on the side it leaves, at any scale; a fixed offset such as
points + 1e-3 * normals does, or skips thin gaps. origins, directions, t and ids as for
surface(); new_directions: (M, 3). Returns float32 (M, 3) (float64 for a double scene). For a
miss: surface()'s point.)doc";

constexpr const char* kIntersectAllDoc =
    R"doc(intersect_all(self, origins, directions, max_hits=16, tmin=0.0, tmax=math.inf,
              mask=0xffffffff)
--

Every crossing of each ray with the spheres' surfaces, not only the first.

Returns Crossings(t, ids, exits, counts), a named tuple: t float32 (float64 for a double
scene), ids uint32 and exits bool of
shape (..., max_hits), the first max_hits crossings of each ray in (tmin, tmax), sorted by t,
then id, then entry before exit (a sphere's near root enters it, its far root leaves it); counts
uint64 of shape (...), how many crossings each ray has in all (more than max_hits when they did
not fit). Unused slots hold t = nan, id = NO_HIT, exit = False. The first crossing is
intersect()'s closest hit. Contract: docs/queries.md.)doc";

constexpr const char* kIntersectNearestDoc =
    R"doc(intersect_nearest(self, origins, directions, k=16, tmin=0.0, tmax=math.inf,
                  mask=0xffffffff)
--

The nearest k crossings of each ray alone: intersect_all()'s first k, bit for bit, without
the total. Through the BVH the walk stops at the k-th crossing found so far, as the closest hit
stops at the first (k-buffers, the first layers of transparency).

Returns NearestCrossings(t, ids, exits, counts), a named tuple: t, ids and exits of shape
(..., k) as intersect_all() fills them; counts uint64 of shape (...), how many slots were
written (at most k). Contract: docs/queries.md.)doc";

constexpr const char* kCountHitsDoc =
    R"doc(count_hits(self, origins, directions, tmin=0.0, tmax=math.inf, mask=0xffffffff)
--

The number of crossings of each ray with the spheres' surfaces in (tmin, tmax), uint64 of
shape (...): both roots of every sphere the ray's line meets count. From a point to infinity,
an odd count means the point is inside an odd number of spheres.)doc";

constexpr const char* kNearestDoc = R"doc(nearest(self, points, max_distance=math.inf)
--

The sphere nearest each point, by signed distance to its surface |p - c| - r (negative
inside; inside overlapping spheres, the one the point is deepest in), among those within
max_distance.

Returns Nearest(ids, distances, surface_points), a named tuple: uint32 (...), float32 (...) and
float32 (..., 3) (float64 for a double scene), the closest point of that sphere's surface. A point with none: id NO_HIT,
distance max_distance, surface point the point itself.)doc";

constexpr const char* kInsideDoc = R"doc(inside(self, points)
--

Whether each point (..., 3) lies inside any sphere (the open balls: a point on a surface is
outside), bool of shape (...).)doc";

constexpr const char* kOverlappingDoc = R"doc(overlapping(self, centre, radius)
--

The ids (uint32, ascending) of the spheres that overlap the ball of this centre (3,) and
radius: |c - centre| < r + radius (touching is not overlapping). Collision candidates. A
negative or NaN radius, or a NaN centre, gives an empty array.)doc";

constexpr const char* kOverlapsDoc = R"doc(overlaps(self, centers, radii)
--

overlapping() for many balls at once, on all cores with the GIL released: a simulation's broad
phase. centers (..., 3), taken row by row in C order; radii one number or one per row. Returns
Overlaps(offsets, ids), a named tuple in the sparse row layout of scipy's CSR matrices: offsets
(M + 1,) int64 and ids uint32, the ids of ball i (ascending) being ids[offsets[i]:offsets[i +
1]]. Exact for unequal radii: sphere j overlaps ball i when |c_j - centre_i| < r_j + radius_i,
as overlapping() decides it.)doc";

constexpr const char* kOverlappingPairsDoc = R"doc(overlapping_pairs(self)
--

Every pair of the scene's own valid spheres that overlap, (P, 2) uint32: rows (i, j), i < j,
where sphere j overlaps the ball of sphere i (overlapping(centers[i], radii[i])), sorted by i
then j, on all cores with the GIL released. scipy's cKDTree.query_pairs for spheres of any
radii.)doc";

constexpr const char* kRefitDoc = R"doc(refit(self, centers, radii, masks=None)
--

Moves the scene's spheres.

New centres and radii for the same spheres (the same N; ids unchanged); masks=None keeps
the spheres' masks, an array replaces them. With a BVH the tree keeps its shape and only its
boxes are updated: much cheaper than a new Scene, but tracing slows down as spheres drift
far from where the tree was built. Waits for queries in flight in other threads.)doc";

constexpr const char* kPinholeDoc =
    R"doc(pinhole_rays(eye, target, up, vfov_deg, width, height)
--

Camera rays of a pinhole camera, one through each pixel's centre: Rays(origins, directions),
a named tuple.

eye, target, up: 3-vectors; vfov_deg: the vertical field of view in degrees, in (0, 180).
Both are float32 arrays of shape (height, width, 3), row 0 at the top of the image;
directions are unit vectors, so intersect() returns distances. The camera is the renderer's
(Ray Tracing in One Weekend's). Raises ValueError if eye == target, up is parallel to the
view direction, a value is not finite, or the size is not positive.)doc";

constexpr const char* kRenderDoc =
    R"doc(render(scene="rtiow-final", mode="normals", width=None, height=None, spp=4, seed=0,
       threads=0, accel="auto", max_depth=50, time_limit=0.0, camera=None, colors=None,
       materials=None, linear=False)
--

Renders a scene to an image: one of the renderer's, or spheres of your own, as a uint8 array
(height, width, 3).

scene: a preset ("single", "three", "rtiow-final", "random:N"), a JSON scene file, a
sphray.Scene, or (centers, radii) arrays (the renderer is float: a double scene's spheres are
rounded to float). Your own spheres are grey Lambertian, or coloured by
colors (N, 3) in [0, 1], with materials (one dict, or one per sphere) as scene files write
them ({"type": "metal", "albedo": [...], "fuzz": 0.1}, ...); without a camera they are framed
whole from +z. camera: a dict as
scene files write one ("lookfrom", "lookat", "vup", "vfov", "defocus_angle", "focus_dist"),
replacing the scene's. linear=True (path mode): the mean radiance of each pixel as float32,
linear and unclamped, instead of bytes.
mode: "normals", "flat", "depth", "id", "shaded" or "path". width, height: the scene's own
size when neither is given, its aspect when one is. spp: samples per pixel; threads: 0 for
all cores; time_limit: path mode, seconds after which no sample is started (0: none). The
same image as `sphray render` with the same options, and the same defaults. Raises ValueError
for an unknown scene or mode or a value out of range; Ctrl-C stops it with KeyboardInterrupt.)doc";

constexpr const char* kLoadDoc = R"doc(load(path, radius=None)
--

The particles of a particle file: Particles(centers, radii, colors), a named tuple that
sphray.Scene(p.centers, p.radii) takes as it is.

path: a .sphp, .xyz, .csv, .ply or .pdb file (docs/scenes.md, "Particle files"), its format
chosen by its extension. radius: the radius of every particle of a text or PLY file without a
radius (ignored for a file that has one, and for .sphp and .pdb). centers float32 (N, 3), radii float32 (N,),
colors float32 (N, 3) in [0, 1] or None when the file has no colour columns (.sphp never has).

A .sphp file is not read but mapped: centers and radii are read-only views of one
numpy.memmap of its records (centers = m[:, :3], radii = m[:, 3]), after its header (magic,
version, count) and its exact size are checked. The views are strided; Scene copies them once
into its own layout. A .sphp file truncated or rewritten while it is mapped can kill the
process with SIGBUS when the pages are read; copy the arrays (np.array(p.centers)) to let go
of the file. A text file is read into fresh arrays. Raises ValueError with the reader's
one-line message, "FILE:LINE: expected ...", for a file that cannot be read as particles.)doc";

// obj as JSON text, for the renderer's scene parser; numpy values go through their tolist().
std::string as_json(const py::handle& obj) {
  const py::object tolist = py::module_::import("operator").attr("methodcaller")("tolist");
  return py::module_::import("json").attr("dumps")(obj, "default"_a = tolist).cast<std::string>();
}

// materials (one dict, or one per sphere) as r's distinct JSON texts and each sphere's index
// among them: a list that repeats a few dicts (the usual [glass] * n) is turned into JSON once
// per dict, not once per sphere.
void materials_of(const py::object& materials, RenderRequest& r) {
  if (py::isinstance<py::dict>(materials)) {
    r.materials.emplace_back(as_json(materials), 0);
    return;
  }
  const py::list list(materials);
  const std::size_t n = r.spheres->size();
  if (list.size() != n) {
    throw py::value_error("materials: expected one, or one per sphere (" + std::to_string(n) +
                          "), got " + std::to_string(list.size()));
  }
  std::unordered_map<PyObject*, std::uint32_t> by_object;
  std::unordered_map<std::string, std::uint32_t> by_text;
  r.material_of.reserve(n);
  for (const py::handle& material : list) {
    auto [seen, fresh] = by_object.try_emplace(material.ptr(), 0);
    if (fresh) {
      const std::size_t sphere = r.material_of.size();
      auto [text, new_text] =
          by_text.try_emplace(as_json(material), static_cast<std::uint32_t>(r.materials.size()));
      if (new_text) r.materials.emplace_back(text->first, sphere);
      seen->second = text->second;
    }
    r.material_of.push_back(seen->second);
  }
}

// Whether self, a sphray.Scene (or an instance of a Python subclass), holds its C++ Scene yet.
bool constructed(py::handle self) {
  auto* instance = reinterpret_cast<py::detail::instance*>(self.ptr());
  return instance->get_value_and_holder().holder_constructed();
}

// The Scene self holds. pybind11 hands a method an instance whose __init__ never ran
// (sphray.Scene.__new__(sphray.Scene)) as if it held one, and the method then reads garbage:
// every method reaches its Scene through here instead, and such an instance raises.
Scene& scene_in(py::handle self) {
  if (!py::isinstance<Scene>(self)) {
    throw py::type_error("expected a sphray.Scene, got " +
                         std::string(py::str(py::type::of(self))));
  }
  if (!constructed(self)) throw std::runtime_error("sphray.Scene: __init__ was never called");
  return self.cast<Scene&>();
}

// method as a binding that takes self through scene_in().
template <typename R, typename... A>
auto on_scene(R (Scene::*method)(A...) const) {
  return [method](py::handle self, A... args) -> R { return (scene_in(self).*method)(args...); };
}
template <typename R, typename... A>
auto on_scene(R (Scene::*method)(A...)) {
  return [method](py::handle self, A... args) -> R { return (scene_in(self).*method)(args...); };
}

std::vector<std::string> supported_isa_names() {
  std::vector<std::string> names;
  for (sphray::Isa isa : sphray::supported_isas())
    names.emplace_back(sphray::isa_name(isa));
  return names;
}

}  // namespace

PYBIND11_MODULE(sphray, m) {
  // The docstrings open with the Python signature in CPython's text-signature form
  // ("name(args)\n--\n\n"), which inspect.signature() and help() read and which the stubtest
  // check compares with sphray.pyi; pybind11's own would name C++ handle types. Defaults are
  // written as inspect can evaluate them: Python literals, and infinity as math.inf.
  py::options options;
  options.disable_function_signatures();
  m.doc() = kModuleDoc;
  m.attr("__version__") = sphray::kVersion;
  m.attr("NO_HIT") = py::int_(sphray::kNoHit);
  sphray::python::add_result_types(m);
  // A call stopped by a signal (interruption.hpp) raises what the handler raised.
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const sphray::python::Interrupted&) {
      if (!PyErr_Occurred()) PyErr_SetNone(PyExc_KeyboardInterrupt);
    }
  });

  py::class_<Scene> scene_class(m, "Scene", kSceneDoc);
  scene_class
      .def(py::init<const py::handle&, const py::handle&, const std::string&, const py::handle&,
                    const py::handle&>(),
           py::arg("centers"), py::arg("radii"), py::arg("accel") = "auto",
           py::arg("masks") = py::none(), py::arg("precision") = py::none(), kInitDoc)
      .def("intersect", on_scene(&Scene::intersect), py::arg("origins"), py::arg("directions"),
           py::arg("tmin") = 0.0, py::arg("tmax") = INFINITY, py::arg("mask") = sphray::kAllBits,
           kIntersectDoc)
      .def("occluded", on_scene(&Scene::occluded), py::arg("origins"), py::arg("directions"),
           py::arg("tmin") = 0.0, py::arg("tmax") = INFINITY, py::arg("mask") = sphray::kAllBits,
           kOccludedDoc)
      .def("surface", on_scene(&Scene::surface), py::arg("origins"), py::arg("directions"),
           py::arg("t"), py::arg("ids"), kSurfaceDoc)
      .def("spawn", on_scene(&Scene::spawn), py::arg("origins"), py::arg("directions"),
           py::arg("t"), py::arg("ids"), py::arg("new_directions"), kSpawnDoc)
      .def("intersect_all", on_scene(&Scene::intersect_all), py::arg("origins"),
           py::arg("directions"), py::arg("max_hits") = 16, py::arg("tmin") = 0.0,
           py::arg("tmax") = INFINITY, py::arg("mask") = sphray::kAllBits, kIntersectAllDoc)
      .def("intersect_nearest", on_scene(&Scene::intersect_nearest), py::arg("origins"),
           py::arg("directions"), py::arg("k") = 16, py::arg("tmin") = 0.0,
           py::arg("tmax") = INFINITY, py::arg("mask") = sphray::kAllBits, kIntersectNearestDoc)
      .def("count_hits", on_scene(&Scene::count_hits), py::arg("origins"), py::arg("directions"),
           py::arg("tmin") = 0.0, py::arg("tmax") = INFINITY, py::arg("mask") = sphray::kAllBits,
           kCountHitsDoc)
      .def("nearest", on_scene(&Scene::nearest), py::arg("points"),
           py::arg("max_distance") = INFINITY, kNearestDoc)
      .def("inside", on_scene(&Scene::inside), py::arg("points"), kInsideDoc)
      .def("overlapping", on_scene(&Scene::overlapping), py::arg("centre"), py::arg("radius"),
           kOverlappingDoc)
      .def("overlaps", on_scene(&Scene::overlaps), py::arg("centers"), py::arg("radii"),
           kOverlapsDoc)
      .def("overlapping_pairs", on_scene(&Scene::overlapping_pairs), kOverlappingPairsDoc)
      .def("refit", on_scene(&Scene::refit), py::arg("centers"), py::arg("radii"),
           py::arg("masks") = py::none(), kRefitDoc)
      .def("__len__", on_scene(&Scene::size),
           "__len__(self)\n--\n\nlen(scene): the number of spheres.")
      .def_property_readonly("uses_bvh", on_scene(&Scene::uses_bvh),
                             "Whether a BVH answers the queries (else brute force).")
      .def_property_readonly("precision", on_scene(&Scene::precision),
                             "'float' or 'double': the kernel the queries run, and the float "
                             "dtype of the arrays they read and return (float32, float64).")
      .def_property_readonly("centers", on_scene(&Scene::centers),
                             "A read-only view of the (N, 3) array the scene reads (float32, or "
                             "float64 for a double scene): yours if not copied.")
      .def_property_readonly("radii", on_scene(&Scene::radii),
                             "A read-only view of the (N,) array the scene reads (float32, or "
                             "float64 for a double scene): yours if not copied.")
      .def("__repr__", [](py::handle self) {
        const Scene& s = scene_in(self);
        return "<sphray.Scene: " + std::to_string(s.size()) + " spheres, " +
               (s.uses_bvh() ? "BVH" : "brute force") + ", " + s.precision() + ">";
      });
  // pybind11 ignores a second __init__ on a constructed instance without a word. A scene's
  // spheres change only through refit() (same count, ids kept, queries in other threads waited
  // for), so __init__ on a live scene raises instead (docs/python.md, "Calling __init__ again").
  // The wrapper cannot be named __init__ itself: pybind11 treats any function of that name as a
  // constructor and skips it the same way.
  py::object construct = scene_class.attr("__init__");
  scene_class.attr("__init__") = py::cpp_function(
      [construct, type = py::type::of<Scene>()](py::handle self, py::args args, py::kwargs kwargs) {
        if (!py::isinstance(self, type)) {
          throw py::type_error("Scene.__init__: self must be a sphray.Scene, got " +
                               std::string(py::str(py::type::of(self))));
        }
        if (constructed(self)) {
          throw std::runtime_error(
              "Scene.__init__: this scene is already initialised; make a new Scene, or move "
              "its spheres with refit()");
        }
        construct(self, *args, **kwargs);
      },
      py::name("init"), py::is_method(scene_class), py::doc(kInitDoc));

  m.def("load", &sphray::python::load_particles, py::arg("path"), py::arg("radius") = py::none(),
        kLoadDoc);
  m.def("pinhole_rays", &sphray::python::pinhole_rays, py::arg("eye"), py::arg("target"),
        py::arg("up"), py::arg("vfov_deg"), py::arg("width"), py::arg("height"), kPinholeDoc);

  m.def(
      "render",
      [m](const py::object& scene, const std::string& mode, std::optional<int> width,
          std::optional<int> height, int spp, std::uint64_t seed, int threads,
          const std::string& accel, int max_depth, double time_limit, const py::object& camera,
          const py::object& colors, const py::object& materials, bool linear) {
        RenderRequest r;
        r.mode = mode;
        r.width = width;
        r.height = height;
        r.spp = spp;
        r.seed = seed;
        r.threads = threads;
        r.accel = accel;
        r.max_depth = max_depth;
        r.time_limit = time_limit;
        if (py::isinstance<Scene>(scene) || py::isinstance<py::tuple>(scene)) {
          // The caller's spheres: a Scene, or (centers, radii) made into one.
          const py::object own =
              py::isinstance<Scene>(scene) ? scene : m.attr("Scene")(*scene, "accel"_a = "brute");
          r.spheres = scene_in(own).copy_spheres();
          if (!colors.is_none()) r.colors = sphray::python::colors_of(colors, r.spheres->size());
          if (!materials.is_none()) materials_of(materials, r);
        } else {
          // A preset name, or a scene file as str or pathlib.Path (os.fspath takes both).
          r.scene = py::module_::import("os").attr("fspath")(scene).cast<std::string>();
          if (!colors.is_none() || !materials.is_none()) {
            throw py::value_error(
                "colors, materials: only for spheres of your own (a Scene or arrays)");
          }
        }
        if (!camera.is_none()) r.camera = as_json(camera);  // parsed as a scene file's camera
        r.linear = linear;
        return sphray::python::render(r);
      },
      py::arg("scene") = "rtiow-final", py::arg("mode") = "normals", py::arg("width") = py::none(),
      py::arg("height") = py::none(), py::arg("spp") = RenderRequest{}.spp, py::arg("seed") = 0,
      py::arg("threads") = 0, py::arg("accel") = "auto", py::arg("max_depth") = 50,
      py::arg("time_limit") = 0.0, py::arg("camera") = py::none(), py::arg("colors") = py::none(),
      py::arg("materials") = py::none(), py::arg("linear") = false, kRenderDoc);

  m.def(
      "active_isa", [] { return std::string(sphray::isa_name(sphray::active_isa())); },
      "active_isa()\n--\n\nThe instruction set the queries use: 'scalar', 'sse4.2', 'avx2', "
      "'avx512' or 'neon'.");
  m.def(
      "bvh_isa",
      [](std::optional<std::size_t> sphere_count) {
        return std::string(
            sphray::isa_name(sphere_count ? sphray::bvh_isa(*sphere_count) : sphray::bvh_isa()));
      },
      py::arg("sphere_count") = py::none(),
      "bvh_isa(sphere_count=None)\n--\n\nThe instruction set the tree of a Scene of sphere_count "
      "spheres (None: many) is laid out "
      "for and walked with: the fastest for trees of that size on this CPU, by a rule on its "
      "vendor and family, or SPHRAY_ISA's.");
  m.def("supported_isas", &supported_isa_names,
        "supported_isas()\n--\n\nThe instruction sets this build has and this machine runs, best "
        "first (the values "
        "SPHRAY_ISA may take here).");
}
