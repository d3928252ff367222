// sphray.load(path, radius=None): a particle file's spheres as numpy arrays, a .sphp file's as
// views of a numpy.memmap of it.
#pragma once

#include <pybind11/pybind11.h>

#include <optional>
#include <string>

namespace sphray::python {

namespace py = pybind11;

/// Particles(centers, radii, colors) of the file at path. Raises ValueError with the reader's
/// one-line message (FILE:LINE: ...).
py::tuple load_particles(const py::object& path, std::optional<float> radius);

}  // namespace sphray::python
