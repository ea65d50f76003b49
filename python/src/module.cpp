// The Python module hedra._hedra (python/hedra/__init__.py re-exports it): exceptions, the
// version, and the helpers shared by body.cpp and scene.cpp. Arrays cross the boundary as
// copies (numpy in, numpy out), so nothing in Python aliases hedra's immutable geometry.
#include <pybind11/stl.h>

#include "common.h"

namespace hedra::python {

Vec3 vec3(const py::handle& value, const char* what) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  } catch (const py::error_already_set&) {
  }
  if (!a || a.size() != 3 || a.ndim() != 1) {
    PyErr_Clear();
    throw InvalidInput(std::string(what) + ": expected 3 numbers (x, y, z), got " +
                       std::string(py::str(value)));
  }
  return Vec3(a.at(0), a.at(1), a.at(2));
}

py::array_t<double> points_array(const std::vector<Vec3>& points) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  auto w = out.mutable_unchecked<2>();
  for (size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) w(static_cast<py::ssize_t>(i), k) = points[i][k];
  return out;
}

py::array_t<double> rows_array(const std::vector<double>& flat, size_t columns) {
  const size_t rows = columns ? flat.size() / columns : 0;
  py::array_t<double> out({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(columns)});
  if (!flat.empty()) std::copy(flat.begin(), flat.end(), out.mutable_data());
  return out;
}

void rethrow_with_source(const PyScene& scene, const InvalidInput& e) {
  if (scene.source.empty()) throw e;
  throw InvalidInput(scene.source + ": " + e.what());
}

}  // namespace hedra::python

PYBIND11_MODULE(_hedra, m) {
  namespace py = pybind11;
  using namespace hedra::python;
  m.doc() = "hedra: exact solid modeling of polyhedral scenes (docs/python.md)";
  m.attr("__version__") = hedra::kVersion;
  // One-line messages naming the file and the place, as the command prints them.
  py::register_exception<hedra::InvalidInput>(m, "InvalidInput", PyExc_ValueError);
  py::register_exception<hedra::IoError>(m, "IoError", PyExc_OSError);
  py::register_exception<hedra::DecompositionFailed>(m, "DecompositionFailed", PyExc_RuntimeError);
  // Every cancelled pass (decomposition, hidden lines, shadows, rendering).
  py::register_exception<hedra::Cancelled>(m, "Cancelled", PyExc_RuntimeError);
  bind_body(m);
  bind_scene(m);
}
