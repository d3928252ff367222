#include "particles_load.hpp"

#include <pybind11/numpy.h>

#include <algorithm>
#include <filesystem>

#include "results.hpp"
#include "sphray/particles/particles.hpp"

namespace sphray::python {
namespace {

bool is_sphp(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c + 32) : c; });
  return ext == ".sphp";
}

// The records of a .sphp file, mapped rather than read: its header (magic, version, count and
// the file's exact size) is checked first by the reader's own SphpFile, so the map covers
// exactly count records. The views keep the map alive.
py::tuple map_sphp(const py::object& path_object, const std::filesystem::path& path) {
  std::uint64_t count = 0;
  {
    const particles::SphpFile file(path);  // throws ParticleError; closed at once
    count = file.count();
  }
  py::object records;
  if (count == 0) {  // mmap refuses an empty range
    records = py::array_t<float>(std::vector<py::ssize_t>{0, 4});
  } else {
    records = py::module_::import("numpy").attr("memmap")(
        path_object, py::arg("dtype") = "<f4", py::arg("mode") = "r",
        py::arg("offset") = particles::kSphpHeaderBytes,
        py::arg("shape") = py::make_tuple(count, 4));
  }
  const py::object all = py::slice(py::none(), py::none(), py::none());
  const py::object centers = records[py::make_tuple(all, py::slice(0, 3, 1))];
  const py::object radii = records[py::make_tuple(all, 3)];
  return make_result(Result::particles, {centers, radii, py::none()});
}

py::tuple read_text(const std::filesystem::path& path, std::optional<float> radius) {
  particles::Points points = particles::read_particle_file(path, {radius});
  const SphereView v = points.spheres.view();
  const auto n = static_cast<py::ssize_t>(v.count);
  py::array_t<float> centers({n, py::ssize_t{3}});
  py::array_t<float> radii(n);
  auto c = centers.mutable_unchecked<2>();
  auto r = radii.mutable_unchecked<1>();
  for (py::ssize_t i = 0; i < n; ++i) {
    c(i, 0) = v.cx[i];
    c(i, 1) = v.cy[i];
    c(i, 2) = v.cz[i];
    r(i) = v.radius[i];
  }
  py::object colors = py::none();
  if (!points.colors.empty()) {
    py::array_t<float> rgb({n, py::ssize_t{3}});
    auto k = rgb.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
      const Vec3 color = points.colors[static_cast<std::size_t>(i)];
      k(i, 0) = color.x;
      k(i, 1) = color.y;
      k(i, 2) = color.z;
    }
    colors = std::move(rgb);
  }
  return make_result(Result::particles, {centers, radii, colors});
}

}  // namespace

py::tuple load_particles(const py::object& path_object, std::optional<float> radius) {
  const auto path = std::filesystem::path(
      py::module_::import("os").attr("fsencode")(path_object).cast<std::string>());
  try {
    if (is_sphp(path)) return map_sphp(path_object, path);
    return read_text(path, radius);
  } catch (const particles::ParticleError& e) {
    throw py::value_error(e.what());
  }
}

}  // namespace sphray::python
