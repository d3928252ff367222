#include "arrays.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace sphray::python {
namespace {

// An array of S's strides in whole elements, or false when it does not hold S (holds()) or
// some stride is not a multiple of sizeof(S): such arrays are converted rather than read
// through a misaligned pointer.
template <Scalar S>
bool element_strides(const py::array& a, std::vector<std::ptrdiff_t>& strides) {
  if (!holds<S>(a)) return false;
  strides.clear();
  for (py::ssize_t d = 0; d < a.ndim(); ++d) {
    if (a.strides(d) % static_cast<py::ssize_t>(sizeof(S)) != 0) return false;
    strides.push_back(a.strides(d) / static_cast<py::ssize_t>(sizeof(S)));
  }
  return true;
}

// a's data as S with its strides in elements: a itself when element_strides() can read it, else
// its C-contiguous copy of dtype S (which it always can). Returns the array data points into.
template <Scalar S>
py::array readable(const char* what, const py::array& a, std::vector<std::ptrdiff_t>& strides) {
  if (element_strides<S>(a, strides)) return a;
  py::array copy = converted<S, py::array::c_style>(what, a);
  element_strides<S>(copy, strides);
  return copy;
}

// a with its leading axes merged into one, as a view where numpy can make one (always for
// contiguous data), else a copy: (..., k) to (n, k), or (...) to (n,) when keep_last is false.
py::array flatten_leading(const char* what, const py::array& a, bool keep_last) {
  return numpy_call(what, [&]() -> py::array {
    if (keep_last) return a.attr("reshape")(-1, a.shape(a.ndim() - 1));
    return a.attr("reshape")(-1);
  });
}

std::vector<py::ssize_t> shape_of(const py::array& a) {
  return {a.shape(), a.shape() + a.ndim()};
}

std::string shape_text(const std::vector<py::ssize_t>& shape) {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (i > 0) s += ", ";
    s += std::to_string(shape[i]);
  }
  return s + (shape.size() == 1 ? ",)" : ")");
}

// Checks that every value of the flat integer array a, converted to T (int64 for signed
// dtypes, uint64 for unsigned: either holds every value of its kind), lies in [0, 2^32 - 1].
template <typename T>
std::vector<std::uint32_t> checked_uint32(const char* what, const py::array& a, const char* kind,
                                          bool scalar) {
  const auto wide = converted<T, py::array::c_style>(what, a);
  std::vector<std::uint32_t> values(static_cast<std::size_t>(wide.size()));
  const T* v = wide.data();
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::in_range<std::uint32_t>(v[i])) {
      throw py::value_error(std::string(what) + ": " + kind + " must lie in [0, 2**32 - 1], got " +
                            std::to_string(v[i]) +
                            (scalar ? "" : " at flat index " + std::to_string(i)));
    }
    values[i] = static_cast<std::uint32_t>(v[i]);
  }
  return values;
}

// A Python int (bool included, as Python counts it) anywhere in or beyond int64's range.
std::uint32_t python_int_as_uint32(const char* what, const py::handle& obj, const char* kind) {
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(obj.ptr(), &overflow);
  if (v == -1 && PyErr_Occurred()) throw py::error_already_set();
  if (overflow != 0 || v < 0 || v > 0xffffffffLL) {
    throw py::value_error(std::string(what) + ": " + kind + " must lie in [0, 2**32 - 1], got " +
                          std::string(py::str(obj)));
  }
  return static_cast<std::uint32_t>(v);
}

}  // namespace

std::string shape_text(const py::array& array) {
  return shape_text(shape_of(array));
}

void rethrow_numpy_error(const char* what, py::error_already_set& e) {
  // Not numpy's exception class itself: _ArrayMemoryError, for one, takes no message.
  PyObject* type = e.matches(PyExc_MemoryError)  ? PyExc_MemoryError
                   : e.matches(PyExc_TypeError)  ? PyExc_TypeError
                   : e.matches(PyExc_ValueError) ? PyExc_ValueError
                                                 : nullptr;
  if (type == nullptr) throw;
  std::string message = py::str(e.value());
  if (message.empty()) message = type == PyExc_MemoryError ? "out of memory" : "cannot convert";
  py::raise_from(e, type, (std::string(what) + ": " + message).c_str());
  throw py::error_already_set();
}

py::array as_real_array(const char* what, const py::handle& obj) {
  py::array a =
      numpy_call(what, [&] { return py::array(py::reinterpret_borrow<py::object>(obj)); });
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    throw py::type_error(std::string(what) + ": expected a float or integer dtype, got " +
                         std::string(py::str(a.dtype())) + " with shape " + shape_text(a));
  }
  return a;
}

template <Scalar S>
Vec3Rows<S>::Vec3Rows(const char* what, const py::handle& obj) {
  py::array a = as_real_array(what, obj);
  if (a.ndim() < 2 || a.shape(a.ndim() - 1) != 3) {
    throw py::value_error(std::string(what) + ": expected shape (M, 3) (or (..., 3)), got " +
                          shape_text(a));
  }
  shape_ = shape_text(a);
  leading_ = shape_of(a);
  leading_.pop_back();
  std::vector<std::ptrdiff_t> strides;
  array_ = readable<S>(what, flatten_leading(what, a, true), strides);
  data_ = static_cast<const S*>(array_.data());
  rows_ = static_cast<std::size_t>(array_.shape(0));
  row_stride_ = strides[0];
  col_stride_ = strides[1];
}

template <Scalar S>
ScalarPerRow<S>::ScalarPerRow(const char* what, const py::handle& obj,
                              const std::vector<py::ssize_t>& shape) {
  if (PyFloat_Check(obj.ptr()) || (PyLong_Check(obj.ptr()) && !PyBool_Check(obj.ptr()))) {
    // A Python number as Python converts it: an int beyond float's range is OverflowError.
    const double v = PyFloat_AsDouble(obj.ptr());
    if (v == -1.0 && PyErr_Occurred()) throw py::error_already_set();
    scalar_ = static_cast<S>(v);
    return;
  }
  py::array a = as_real_array(what, obj);
  if (a.ndim() == 0) {  // a numpy scalar (np.float32(10), m[0]) or a 0-d array
    scalar_ = static_cast<S>(*converted<double, py::array::c_style>(what, a).data());
    return;
  }
  if (shape_of(a) != shape) {
    throw py::value_error(std::string(what) + ": expected a scalar or shape " + shape_text(shape) +
                          " (one per ray), got " + shape_text(a));
  }
  std::vector<std::ptrdiff_t> strides;
  array_ = readable<S>(what, flatten_leading(what, a, false), strides);
  data_ = static_cast<const S*>(array_.data());
  stride_ = strides[0];
}

template class Vec3Rows<float>;
template class Vec3Rows<double>;
template class ScalarPerRow<float>;
template class ScalarPerRow<double>;

// The values of an integer array of the given shape as uint32: ids or masks ("kind").
std::vector<std::uint32_t> uint32_values(const char* what, const py::handle& obj,
                                         const std::vector<py::ssize_t>& shape, const char* kind,
                                         const char* per) {
  py::array a = as_real_array(what, obj);
  if (a.dtype().kind() == 'f') {
    throw py::type_error(std::string(what) + ": expected an integer dtype (uint32 " + kind +
                         "), got " + std::string(py::str(a.dtype())) + " with shape " +
                         shape_text(a));
  }
  if (shape_of(a) != shape) {
    throw py::value_error(std::string(what) + ": expected shape " + shape_text(shape) + " (one " +
                          per + "), got " + shape_text(a));
  }
  const py::array flat = flatten_leading(what, a, false);
  const bool scalar = a.ndim() == 0;
  if (a.dtype().kind() == 'u') return checked_uint32<std::uint64_t>(what, flat, kind, scalar);
  return checked_uint32<std::int64_t>(what, flat, kind, scalar);
}

std::vector<std::uint32_t> ids_per_row(const char* what, const py::handle& obj,
                                       const std::vector<py::ssize_t>& shape) {
  return uint32_values(what, obj, shape, "ids", "per ray");
}

MaskPerRow::MaskPerRow(const py::handle& obj, const std::vector<py::ssize_t>& shape) {
  if (PyLong_Check(obj.ptr())) {  // every ray's mask, a Python int of any size
    scalar_ = python_int_as_uint32("mask", obj, "masks");
    return;
  }
  const py::array a = as_real_array("mask", obj);
  if (a.ndim() == 0) {  // every ray's mask, a numpy integer (np.uint32(1), m[0]) or 0-d array
    scalar_ = uint32_values("mask", a, {}, "masks", "per ray")[0];
  } else {
    values_ = uint32_values("mask", a, shape, "masks", "per ray");
  }
}

py::array read_only_view(const py::array& a) {
  py::array view = a.attr("view")();
  view.attr("setflags")(py::arg("write") = false);
  return view;
}

}  // namespace sphray::python
