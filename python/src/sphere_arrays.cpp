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

// a as the float32 copy the scene keeps (made only when a is not one already, so never the
// caller's array): read-only, so that nothing can change the spheres brute force reads
// without the tree seeing it too.
template <int Flags>
py::array own_copy(const char* what, const py::array& a) {
  py::array copy = converted<float, Flags>(what, a);
  if (!copy.is(a)) copy.attr("setflags")(py::arg("write") = false);
  return copy;
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
  // The C API's limit, for the same reason: ids are uint32, and NO_HIT = 2^32 - 1 is then no
  // sphere's id. Checked before any copy is attempted.
  if (static_cast<std::size_t>(c.shape(0)) > kNoHit) {
    throw py::value_error(
        "centers: at most 2**32 - 1 spheres (ids are uint32 and NO_HIT = 2**32 - 1 is no "
        "sphere's), got shape " +
        shape_text(c));
  }
  centers_ = columns_contiguous(c) ? c : own_copy<py::array::f_style>("centers", c);
  radii_ = is_float32(r) && (r.shape(0) <= 1 || r.strides(0) == kFloat)
               ? r
               : own_copy<py::array::c_style>("radii", r);
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
