// The named tuples the queries return (sphray.Hits, sphray.Surface, ...): a result unpacks
// positionally as the plain tuple it was, and also names its fields (hits.t, hits.ids), as
// Open3D's RaycastingScene names its arrays.
//
// The classes are collections.namedtuple types made once, when the module is imported
// (add_result_types), and kept for the life of the process: a call builds an instance of one,
// never a class.
#pragma once

#include <pybind11/pybind11.h>

#include <cstddef>
#include <initializer_list>

namespace sphray::python {

namespace py = pybind11;

/// The result types, in the order of kResultTypes (results.cpp).
enum class Result : std::size_t {
  hits,
  surface,
  crossings,
  nearest_crossings,
  nearest,
  overlaps,
  rays,
  particles,
  count
};

/// Makes the namedtuple classes and adds them to the module m, by name (m.Hits, ...).
void add_result_types(py::module_& m);

/// An instance of the result type `type` holding fields, in the order of its fields. The
/// number of fields must be the type's own.
py::tuple make_result(Result type, std::initializer_list<py::handle> fields);

}  // namespace sphray::python
