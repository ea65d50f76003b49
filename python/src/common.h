// Shared declarations of the Python module's translation units (python/src/*.cpp).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "hedra/hedra.h"

namespace hedra::python {

namespace py = pybind11;

/// hedra.Body: a Body and, for curved primitives, the analytic surface that smooth shading
/// uses once the body is in a scene (it follows the body's transformations).
struct PyBody {
  Body body;
  SmoothSurface surface;
};

/// hedra.Scene: a Scene and the file it was read from ("" when built in Python), which
/// messages and the shadows report name as the command does.
struct PyScene {
  Scene scene;
  std::string source;
};

/// A 3-vector from any sequence of 3 numbers (list, tuple, numpy array).
/// \throw InvalidInput naming `what`.
Vec3 vec3(const py::handle& value, const char* what);
/// (n, 3) float64 copy of points.
py::array_t<double> points_array(const std::vector<Vec3>& points);
/// (k, 6) float64 copy of segments given as flat x1 y1 z1 x2 y2 z2 rows.
py::array_t<double> rows_array(const std::vector<double>& flat, size_t columns);
/// Prefixes the scene's file to an InvalidInput message, as the command does.
[[noreturn]] void rethrow_with_source(const PyScene& scene, const InvalidInput& e);

void bind_body(py::module_& m);
void bind_scene(py::module_& m);

}  // namespace hedra::python
