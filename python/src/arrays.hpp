// Reading numpy arrays for the module: shape and dtype checks with numpy's exceptions, and
// data of the scene's precision (float32 for a float scene, float64 for a double one) read in
// place wherever the layout allows it.
//
// Every reader keeps the array it reads from (the caller's, or the one conversion made of it)
// alive for as long as it lives, and exposes plain pointers and element strides
// that may be used with the GIL released.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "sphray/sphray.hpp"

namespace sphray::python {

namespace py = pybind11;

/// "(4, 3)": a shape as numpy prints it.
std::string shape_text(const py::array& array);

/// Re-raises e, numpy's error while converting the argument what, as the same kind of Python
/// exception with what in front of numpy's message and numpy's exception as its cause:
/// MemoryError when a copy could not be allocated, ValueError or TypeError for input numpy
/// cannot convert. Any other exception (KeyboardInterrupt, say) propagates unchanged.
[[noreturn]] void rethrow_numpy_error(const char* what, py::error_already_set& e);

/// call(), a numpy call on the argument what that may fail (a conversion, a reshape that
/// copies), with its error raised as rethrow_numpy_error says. Every conversion in the module
/// goes through here: pybind11's array_t::ensure() returns a null array and clears the
/// Python error instead, which is how a failed allocation became a segfault.
template <typename Call>
auto numpy_call(const char* what, Call&& call) -> decltype(call()) {
  try {
    return call();
  } catch (py::error_already_set& e) {
    rethrow_numpy_error(what, e);
  }
}

/// obj as an aligned array of T with the layout Flags (py::array::c_style or f_style): obj
/// itself when it is one already, else numpy's converted copy. Errors as numpy_call.
/// Alignment is asked for explicitly: pybind11's flags leave it out, and numpy then returns a
/// misaligned float32 array (a view into packed bytes) as it is, which the readers here cannot
/// read through a float (or double) pointer.
template <typename T, int Flags>
auto converted(const char* what, const py::handle& obj) {
  constexpr int kFlags = Flags | py::array::forcecast | py::detail::npy_api::NPY_ARRAY_ALIGNED_;
  return numpy_call(
      what, [&] { return py::array_t<T, kFlags>(py::reinterpret_borrow<py::object>(obj)); });
}

/// obj as a numpy array of real numbers (float, int or uint dtype), np.asarray(obj). Throws
/// TypeError for any other dtype (bool, complex, object, strings), naming what and the dtype;
/// numpy's own errors (a ragged list, no memory) as numpy_call.
py::array as_real_array(const char* what, const py::handle& obj);

/// Whether a holds S (float32 for float, float64 for double) at an address aligned for S: what
/// the readers may read in place (a view into packed records may be neither).
template <Scalar S>
bool holds(const py::array& a) {
  return a.dtype().is(py::dtype::of<S>()) &&
         reinterpret_cast<std::uintptr_t>(a.data()) % alignof(S) == 0;
}

/// A read-only view of a (the same data): what the Scene's centers and radii attributes give,
/// so that writing through them cannot change the spheres behind the tree's back.
py::array read_only_view(const py::array& a);

/// Rows of three scalars of type S (float or double, the scene's precision), (..., 3): read in
/// place when the array's dtype is S with strides that are whole elements, otherwise converted
/// once to a C-contiguous copy of dtype S.
template <Scalar S>
class Vec3Rows {
 public:
  /// Throws ValueError unless obj's shape is (..., 3) with at least one leading dimension.
  Vec3Rows(const char* what, const py::handle& obj);

  std::size_t size() const { return rows_; }
  /// The shape without its last axis: the shape of one value per row.
  const std::vector<py::ssize_t>& leading_shape() const { return leading_; }
  BasicVec3<S> operator[](std::size_t i) const {
    const S* p = data_ + static_cast<std::ptrdiff_t>(i) * row_stride_;
    return {p[0], p[col_stride_], p[2 * col_stride_]};
  }
  /// The shape the caller gave, as numpy prints it.
  const std::string& shape() const { return shape_; }

 private:
  py::array array_;  // what data_ points into: the caller's array, or its copy of dtype S
  std::string shape_;
  const S* data_ = nullptr;
  std::ptrdiff_t row_stride_ = 0, col_stride_ = 0;  // in elements
  std::size_t rows_ = 0;
  std::vector<py::ssize_t> leading_;
};

/// One scalar of type S per row, for a batch of the given leading shape: a scalar (the same for
/// every row: a Python or numpy number, or a 0-d array) or an array of exactly that shape. Read
/// in place when of dtype S and strided in whole elements.
template <Scalar S>
class ScalarPerRow {
 public:
  ScalarPerRow(const char* what, const py::handle& obj, const std::vector<py::ssize_t>& shape);

  S operator[](std::size_t i) const {
    return data_ == nullptr ? scalar_ : data_[static_cast<std::ptrdiff_t>(i) * stride_];
  }

 private:
  py::array array_;
  const S* data_ = nullptr;  // null: every row takes scalar_
  std::ptrdiff_t stride_ = 0;
  S scalar_ = 0;
};

extern template class Vec3Rows<float>;
extern template class Vec3Rows<double>;
extern template class ScalarPerRow<float>;
extern template class ScalarPerRow<double>;

/// One sphere id per row, an array of exactly the given leading shape with an integer dtype;
/// values outside [0, 2^32 - 1] raise ValueError (an id of no sphere is a miss, as the kernel
/// says, sphray.NO_HIT included).
std::vector<std::uint32_t> ids_per_row(const char* what, const py::handle& obj,
                                       const std::vector<py::ssize_t>& shape);

/// The values of an integer array of the given shape as uint32 ("kind": ids or masks, "per":
/// what one value belongs to, for the messages): TypeError for float dtypes, ValueError for
/// another shape or a value outside [0, 2**32 - 1].
std::vector<std::uint32_t> uint32_values(const char* what, const py::handle& obj,
                                         const std::vector<py::ssize_t>& shape, const char* kind,
                                         const char* per);

/// Ray masks: one integer for every ray (a Python or numpy integer, or a 0-d array) or an
/// integer array of the batch's shape; ValueError for a value outside [0, 2**32 - 1].
class MaskPerRow {
 public:
  MaskPerRow(const py::handle& obj, const std::vector<py::ssize_t>& shape);
  std::uint32_t operator[](std::size_t i) const { return values_.empty() ? scalar_ : values_[i]; }

 private:
  std::uint32_t scalar_ = kAllBits;
  std::vector<std::uint32_t> values_;
};

/// A new C-contiguous array of dtype T with shape leading + trailing.
template <typename T>
py::array_t<T> new_array(const std::vector<py::ssize_t>& leading,
                         std::initializer_list<py::ssize_t> trailing = {}) {
  std::vector<py::ssize_t> shape = leading;
  shape.insert(shape.end(), trailing);
  return py::array_t<T>(shape);
}

}  // namespace sphray::python
