#include "results.hpp"

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace sphray::python {
namespace {

struct Field {
  const char* name;
  const char* doc;
};

struct ResultType {
  const char* name;
  const char* doc;
  std::vector<Field> fields;
};

// Each type's name, docstring and fields, in the order the fields unpack: the names the docs
// (docs/python.md) and the type stubs (sphray.pyi) use, which the stubtest check compares.
const std::array<ResultType, static_cast<std::size_t>(Result::count)> kResultTypes{{
    {"Hits",
     "Scene.intersect()'s closest hit of each ray. Unpacks as t, ids = ...",
     {{"t", "float32, float64 for a double scene (...): the hit's t, or tmax for a miss"},
      {"ids", "uint32 (...): the sphere hit, or NO_HIT"}}},
    {"Surface",
     "Scene.surface(), where each ray meets its hit.",
     {{"points", "float32 or float64, the scene's (..., 3): the points on the spheres"},
      {"normals", "float32 or float64 (..., 3): the outward unit normals (zero for a miss)"},
      {"front_face", "bool (...): whether the ray arrived from outside"}}},
    {"Crossings",
     "Scene.intersect_all(), every crossing of each ray.",
     {{"t",
       "float32 or float64, the scene's (..., max_hits): the crossings' t, sorted; NaN in unused "
       "slots"},
      {"ids", "uint32 (..., max_hits): the spheres crossed; NO_HIT in unused slots"},
      {"exits", "bool (..., max_hits): whether the crossing leaves its sphere"},
      {"counts", "uint64 (...): each ray's crossings in all, max_hits or not"}}},
    {"NearestCrossings",
     "Scene.intersect_nearest(), the nearest k crossings of each ray alone.",
     {{"t",
       "float32 or float64, the scene's (..., k): the crossings' t, sorted; NaN in unused slots"},
      {"ids", "uint32 (..., k): the spheres crossed; NO_HIT in unused slots"},
      {"exits", "bool (..., k): whether the crossing leaves its sphere"},
      {"counts", "uint64 (...): how many slots were written, at most k"}}},
    {"Nearest",
     "Scene.nearest(), the sphere nearest each point.",
     {{"ids", "uint32 (...): the nearest sphere, or NO_HIT"},
      {"distances",
       "float32 or float64, the scene's (...): the signed distance |p - c| - r, negative inside"},
      {"surface_points",
       "float32 or float64 (..., 3): the closest point of that sphere's surface"}}},
    {"Overlaps",
     "Scene.overlaps(), the spheres each ball overlaps, ball i's "
     "in ids[offsets[i]:offsets[i + 1]] (scipy's CSR layout).",
     {{"offsets", "int64 (M + 1,): where each ball's ids start in ids"},
      {"ids", "uint32: the ids of every ball's spheres, ascending within a ball"}}},
    {"Rays",
     "pinhole_rays(), one camera ray through each pixel.",
     {{"origins", "float32 (height, width, 3): the rays' origins"},
      {"directions", "float32 (height, width, 3): their unit directions"}}},
    {"Particles",
     "load(), the particles of a file.",
     {{"centers", "float32 (N, 3): the centres (a view of the file's map for .sphp)"},
      {"radii", "float32 (N,): the radii (a view of the file's map for .sphp)"},
      {"colors", "float32 (N, 3) in [0, 1], or None when the file has no colours"}}},
}};

// The classes, made by add_result_types. Kept (never released) for the life of the process,
// like the module itself: CPython never unloads an extension module.
std::array<PyObject*, static_cast<std::size_t>(Result::count)> classes{};

}  // namespace

void add_result_types(py::module_& m) {
  const py::object namedtuple = py::module_::import("collections").attr("namedtuple");
  for (std::size_t i = 0; i < kResultTypes.size(); ++i) {
    const ResultType& type = kResultTypes[i];
    py::list names;
    for (const Field& field : type.fields)
      names.append(field.name);
    // module="sphray": the repr and pickle find the class as sphray.<name>.
    py::object cls = namedtuple(type.name, names, py::arg("module") = m.attr("__name__"));
    cls.attr("__doc__") = type.doc;
    for (const Field& field : type.fields)
      cls.attr(field.name).attr("__doc__") = field.doc;
    m.attr(type.name) = cls;
    classes[i] = cls.release().ptr();
  }
}

py::tuple make_result(Result type, std::initializer_list<py::handle> fields) {
  const auto i = static_cast<std::size_t>(type);
  if (classes[i] == nullptr || fields.size() != kResultTypes[i].fields.size())
    throw std::logic_error(std::string("make_result: ") + kResultTypes[i].name);
  // What tuple.__new__(cls, fields) does for a subclass, without the Python frame of the
  // namedtuple's own __new__: an instance of the class with the fields as its items.
  auto* cls = reinterpret_cast<PyTypeObject*>(classes[i]);
  PyObject* result = cls->tp_alloc(cls, static_cast<Py_ssize_t>(fields.size()));
  if (result == nullptr) throw py::error_already_set();
  Py_ssize_t k = 0;
  for (const py::handle& field : fields)
    PyTuple_SET_ITEM(result, k++, field.inc_ref().ptr());
  return py::reinterpret_steal<py::tuple>(result);
}

}  // namespace sphray::python
