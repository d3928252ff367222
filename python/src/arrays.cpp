#include "arrays.hpp"

#include <cmath>
#include <cstdint>
#include <limits>

namespace sphray::python {
namespace {

// A float32 array's strides in whole floats, or false when some stride is not a multiple of
// four bytes or the data is misaligned (a view into a packed record, say): such arrays are
// converted rather than read through a misaligned float pointer.
bool float_strides(const py::array& a, std::vector<std::ptrdiff_t>& strides) {
  if (!a.dtype().is(py::dtype::of<float>())) return false;
  if (reinterpret_cast<std::uintptr_t>(a.data()) % alignof(float) != 0) return false;
  strides.clear();
  for (py::ssize_t d = 0; d < a.ndim(); ++d) {
    if (a.strides(d) % static_cast<py::ssize_t>(sizeof(float)) != 0) return false;
    strides.push_back(a.strides(d) / static_cast<py::ssize_t>(sizeof(float)));
  }
  return true;
}

// a with its leading axes merged into one, as a view where numpy can make one (always for
// contiguous data), else a copy: (..., k) to (n, k), or (...) to (n,) when keep_last is false.
py::array flatten_leading(const py::array& a, bool keep_last) {
  if (keep_last) return a.attr("reshape")(-1, a.shape(a.ndim() - 1));
  return a.attr("reshape")(-1);
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

py::array as_float32(const py::array& a) {
  return py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
}

}  // namespace

std::string shape_text(const py::array& array) {
  return shape_text(shape_of(array));
}

py::array as_real_array(const char* what, const py::handle& obj) {
  py::array a = py::array::ensure(obj);
  if (!a) {
    throw py::type_error(std::string(what) + ": expected an array of real numbers, got " +
                         std::string(py::str(py::type::of(obj))));
  }
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    throw py::type_error(std::string(what) + ": expected a float or integer dtype, got " +
                         std::string(py::str(a.dtype())) + " with shape " + shape_text(a));
  }
  return a;
}

Vec3Rows::Vec3Rows(const char* what, const py::handle& obj) {
  py::array a = as_real_array(what, obj);
  if (a.ndim() < 2 || a.shape(a.ndim() - 1) != 3) {
    throw py::value_error(std::string(what) + ": expected shape (M, 3) (or (..., 3)), got " +
                          shape_text(a));
  }
  shape_ = shape_text(a);
  leading_ = shape_of(a);
  leading_.pop_back();
  py::array flat = flatten_leading(a, true);
  std::vector<std::ptrdiff_t> strides;
  if (!float_strides(flat, strides)) {
    flat = as_float32(flat);
    float_strides(flat, strides);
  }
  array_ = flat;
  data_ = static_cast<const float*>(flat.data());
  rows_ = static_cast<std::size_t>(flat.shape(0));
  row_stride_ = strides[0];
  col_stride_ = strides[1];
}

FloatPerRow::FloatPerRow(const char* what, const py::handle& obj,
                         const std::vector<py::ssize_t>& shape) {
  if (py::isinstance<py::float_>(obj) || py::isinstance<py::int_>(obj) ||
      (py::isinstance<py::array>(obj) && py::array::ensure(obj).ndim() == 0)) {
    py::array a = as_real_array(what, obj);
    scalar_ = static_cast<float>(py::cast<double>(a.attr("item")()));
    return;
  }
  py::array a = as_real_array(what, obj);
  if (shape_of(a) != shape) {
    throw py::value_error(std::string(what) + ": expected a scalar or shape " + shape_text(shape) +
                          " (one per ray), got " + shape_text(a));
  }
  py::array flat = flatten_leading(a, false);
  std::vector<std::ptrdiff_t> strides;
  if (!float_strides(flat, strides)) {
    flat = as_float32(flat);
    float_strides(flat, strides);
  }
  array_ = flat;
  data_ = static_cast<const float*>(flat.data());
  stride_ = strides[0];
}

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
  // int64 holds every uint32 and every signed dtype but uint64, whose values above 2^63 wrap
  // negative and are refused below like any other negative value.
  auto wide = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(
      flatten_leading(a, false));
  std::vector<std::uint32_t> values(static_cast<std::size_t>(wide.size()));
  const std::int64_t* v = wide.data();
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (v[i] < 0 || v[i] > std::numeric_limits<std::uint32_t>::max()) {
      throw py::value_error(std::string(what) + ": " + kind + " must lie in [0, 2**32 - 1], got " +
                            std::to_string(v[i]) + " at flat index " + std::to_string(i));
    }
    values[i] = static_cast<std::uint32_t>(v[i]);
  }
  return values;
}

std::vector<std::uint32_t> ids_per_row(const char* what, const py::handle& obj,
                                       const std::vector<py::ssize_t>& shape) {
  return uint32_values(what, obj, shape, "ids", "per ray");
}

MaskPerRow::MaskPerRow(const py::handle& obj, const std::vector<py::ssize_t>& shape) {
  if (py::isinstance<py::int_>(obj)) {  // every ray's mask
    const long long v = obj.cast<long long>();
    if (v < 0 || v > 0xffffffffLL)
      throw py::value_error("mask: masks must lie in [0, 2**32 - 1], got " + std::to_string(v));
    scalar_ = static_cast<std::uint32_t>(v);
  } else if (py::isinstance<py::array>(obj) && py::array::ensure(obj).ndim() == 0) {
    scalar_ = uint32_values("mask", py::array::ensure(obj).attr("reshape")(1), {1}, "masks",
                            "per ray")[0];
  } else {
    values_ = uint32_values("mask", obj, shape, "masks", "per ray");
  }
}

}  // namespace sphray::python
