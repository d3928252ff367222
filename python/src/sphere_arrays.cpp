#include "sphere_arrays.hpp"

#include <cstdint>
#include <string>

#include "arrays.hpp"

namespace sphray::python {
namespace {

// Columns contiguous: each of x, y, z is a run of N elements of S.
template <Scalar S>
bool columns_contiguous(const py::array& centers) {
  constexpr auto size = static_cast<py::ssize_t>(sizeof(S));
  return holds<S>(centers) && (centers.shape(0) <= 1 || centers.strides(0) == size) &&
         centers.strides(1) % size == 0;
}

template <Scalar S>
bool contiguous(const py::array& radii) {
  return holds<S>(radii) &&
         (radii.shape(0) <= 1 || radii.strides(0) == static_cast<py::ssize_t>(sizeof(S)));
}

// a as the copy of dtype S the scene keeps (made only when a is not one already, so never the
// caller's array): read-only, so that nothing can change the spheres brute force reads
// without the tree seeing it too.
template <Scalar S, int Flags>
py::array own_copy(const char* what, const py::array& a) {
  py::array copy = converted<S, Flags>(what, a);
  if (!copy.is(a)) copy.attr("setflags")(py::arg("write") = false);
  return copy;
}

}  // namespace

template <Scalar S>
SphereArrays<S>::SphereArrays(const py::array& c, const py::array& r, const py::handle& masks) {
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
  centers_ = columns_contiguous<S>(c) ? c : own_copy<S, py::array::f_style>("centers", c);
  radii_ = contiguous<S>(r) ? r : own_copy<S, py::array::c_style>("radii", r);
  count_ = static_cast<std::size_t>(c.shape(0));
  const auto* base = static_cast<const char*>(centers_.data());
  const py::ssize_t column = count_ > 0 ? centers_.strides(1) : 0;
  cx_ = reinterpret_cast<const S*>(base);
  cy_ = reinterpret_cast<const S*>(base + column);
  cz_ = reinterpret_cast<const S*>(base + 2 * column);
  r_ = static_cast<const S*>(radii_.data());
  if (!masks.is_none()) masks_ = uint32_values("masks", masks, {c.shape(0)}, "masks", "per sphere");
}

template class SphereArrays<float>;
template class SphereArrays<double>;

}  // namespace sphray::python
