// The spheres a Scene reads: centres and radii from numpy, read in place when their layout is
// already the kernel's structure of arrays, copied once into it otherwise.
//
// The kernel reads each coordinate as its own contiguous column (SphereView, or SphereViewd for
// a double scene). An (N, 3) array of the scene's dtype (float32, or float64 for double) whose
// columns are contiguous (Fortran order, or the transpose of a C-ordered (3, N) array) is that
// already and is read in place; a C-ordered (N, 3) array interleaves x, y, z and is copied once
// into a Fortran-ordered array of that dtype (docs/decisions.md, "Python module", has the
// measurement behind this choice). Radii are read in place when of that dtype and contiguous.
#pragma once

#include <pybind11/numpy.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sphray/sphray.hpp"

namespace sphray::python {

namespace py = pybind11;

/// Spheres of scalar S: float (float32 arrays) or double (float64 arrays).
template <Scalar S>
class SphereArrays {
 public:
  SphereArrays() = default;
  /// centers and radii as as_real_array() returned them. Throws ValueError for shapes other
  /// than (N, 3) and (N,) with the same N. Needs the GIL.
  /// masks: None or an integer array of shape (N,), copied as uint32.
  SphereArrays(const py::array& centers, const py::array& radii, const py::handle& masks);

  /// The kernel's view of the arrays; valid while this object (or a copy of it) lives.
  BasicSphereView<S> view() const {
    return {cx_, cy_, cz_, r_, count_, 0, masks_.empty() ? nullptr : masks_.data()};
  }
  std::size_t size() const { return count_; }

  /// The (N, 3) and (N,) arrays the kernel reads: the caller's own when read in place, else
  /// read-only copies.
  const py::array& centers() const { return centers_; }
  const py::array& radii() const { return radii_; }

  /// Takes other's sphere masks (a copy, none if it has none): refit() without masks keeps the
  /// scene's, as the C API's sphray_scene_refit does.
  void copy_masks_from(const SphereArrays& other) { masks_ = other.masks_; }

 private:
  py::array centers_, radii_;
  const S* cx_ = nullptr;
  const S* cy_ = nullptr;
  const S* cz_ = nullptr;
  const S* r_ = nullptr;
  std::size_t count_ = 0;
  std::vector<std::uint32_t> masks_;  // empty: no masks
};

extern template class SphereArrays<float>;
extern template class SphereArrays<double>;

}  // namespace sphray::python
