#include "sphere_arrays.hpp"

#include <cstdint>
#include <string>

#include "arrays.hpp"

namespace sphray::python {
namespace {

constexpr py::ssize_t kFloat = sizeof(float);

// float32 at a float-aligned address (a view into packed records may be neither).
bool is_float32(const py::array& a) {
  return a.dtype().is(py::dtype::of<float>()) &&
         reinterpret_cast<std::uintptr_t>(a.data()) % alignof(float) == 0;
}

// Columns contiguous: each of x, y, z is a run of N floats.
bool columns_contiguous(const py::array& centers) {
  return is_float32(centers) && (centers.shape(0) <= 1 || centers.strides(0) == kFloat) &&
         centers.strides(1) % kFloat == 0;
}

py::array fortran_float32(const py::array& a) {
  return py::array_t<float, py::array::f_style | py::array::forcecast>::ensure(a);
}

py::array contiguous_float32(const py::array& a) {
  return py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
}

}  // namespace

SphereArrays::SphereArrays(const py::handle& centers, const py::handle& radii,
                           const py::handle& masks) {
  py::array c = as_real_array("centers", centers);
  py::array r = as_real_array("radii", radii);
  if (c.ndim() != 2 || c.shape(1) != 3) {
    throw py::value_error("centers: expected shape (N, 3), got " + shape_text(c));
  }
  if (r.ndim() != 1 || r.shape(0) != c.shape(0)) {
    throw py::value_error("radii: expected shape (" + std::to_string(c.shape(0)) +
                          ",) to match centers " + shape_text(c) + ", got " + shape_text(r));
  }
  if (static_cast<std::size_t>(c.shape(0)) >= kNoHit) {
    throw py::value_error(
        "centers: at most 2**32 - 2 spheres (ids are uint32 and NO_HIT is "
        "reserved), got shape " +
        shape_text(c));
  }
  centers_ = columns_contiguous(c) ? c : fortran_float32(c);
  radii_ = is_float32(r) && (r.shape(0) <= 1 || r.strides(0) == kFloat) ? r : contiguous_float32(r);
  count_ = static_cast<std::size_t>(c.shape(0));
  const auto* base = static_cast<const char*>(centers_.data());
  const py::ssize_t column = count_ > 0 ? centers_.strides(1) : 0;
  cx_ = reinterpret_cast<const float*>(base);
  cy_ = reinterpret_cast<const float*>(base + column);
  cz_ = reinterpret_cast<const float*>(base + 2 * column);
  r_ = static_cast<const float*>(radii_.data());
  if (!masks.is_none()) masks_ = uint32_values("masks", masks, {c.shape(0)}, "masks", "per sphere");
}

}  // namespace sphray::python
