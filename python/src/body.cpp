// hedra.Body, the primitives, Booleans, decomposition and clipping.
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>

#include "common.h"
#include "hedra/baselines/decompose_baselines.h"

namespace hedra::python {
namespace {

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

// (n, 3) float64 from any array-like. \throw InvalidInput naming `what`.
Doubles matrix_of(const py::handle& value, py::ssize_t columns, const char* what) {
  Doubles a;
  try {
    a = Doubles::ensure(value);
  } catch (const py::error_already_set&) {
  }
  if (!a) PyErr_Clear();
  if (a && a.ndim() == 1 && a.size() == 0) a = Doubles(std::vector<py::ssize_t>{0, columns});
  if (!a || a.ndim() != 2 || a.shape(1) != columns)
    throw InvalidInput(std::string(what) + ": expected an (n, " + std::to_string(columns) +
                       ") array of numbers");
  return a;
}

std::vector<Vec3> points_of(const py::handle& value, const char* what) {
  const Doubles a = matrix_of(value, 3, what);
  std::vector<Vec3> out(static_cast<size_t>(a.shape(0)));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) out[static_cast<size_t>(i)] = Vec3(r(i, 0), r(i, 1), r(i, 2));
  return out;
}

int index_of(const py::handle& item, const std::string& where) {
  if (py::isinstance<py::bool_>(item) || !PyIndex_Check(item.ptr()))
    throw InvalidInput(where + ": vertex index " + std::string(py::repr(item)) + " is not an integer");
  const long long v = item.cast<long long>();
  if (v < 0 || v > 0x7fffffff) throw InvalidInput(where + ": vertex index " + std::to_string(v) + " out of range");
  return static_cast<int>(v);
}

bool is_loop_list(const py::handle& face) {
  // A face with holes is a list of loops: its first item is itself a sequence.
  for (const py::handle item : face) return py::isinstance<py::sequence>(item) || py::isinstance<py::array>(item);
  return false;
}

// Faces: each a sequence of vertex indices (outer ring), or a sequence of such loops (outer
// ring, then holes), as Body::faces().
std::vector<Face> faces_of(const py::handle& value) {
  if (!py::isinstance<py::sequence>(value) && !py::isinstance<py::array>(value))
    throw InvalidInput("faces: expected a list of faces (lists of vertex indices)");
  std::vector<Face> faces;
  int f = 0;
  for (const py::handle face : value) {
    const std::string where = "face " + std::to_string(f);
    if (!py::isinstance<py::sequence>(face) && !py::isinstance<py::array>(face))
      throw InvalidInput(where + ": expected a list of vertex indices");
    Face out;
    if (is_loop_list(face)) {
      for (const py::handle loop : face) {
        std::vector<int> ids;
        for (const py::handle i : loop) ids.push_back(index_of(i, where));
        out.loops.push_back(std::move(ids));
      }
    } else {
      std::vector<int> ids;
      for (const py::handle i : face) ids.push_back(index_of(i, where));
      out.loops.push_back(std::move(ids));
    }
    faces.push_back(std::move(out));
    ++f;
  }
  return faces;
}

py::array_t<int> ints_array(const std::vector<int>& ids) {
  py::array_t<int> a(static_cast<py::ssize_t>(ids.size()));
  if (!ids.empty()) std::memcpy(a.mutable_data(), ids.data(), ids.size() * sizeof(int));
  return a;
}

py::list faces_list(const Body& b) {
  py::list out;
  for (const Face& f : b.faces()) {
    if (f.loops.size() == 1) {
      out.append(ints_array(f.loops[0]));
    } else {
      py::list loops;
      for (const auto& l : f.loops) loops.append(ints_array(l));
      out.append(loops);
    }
  }
  return out;
}

py::list faces_plain(const Body& b) {
  // Plain Python lists (pickling): exact and independent of numpy.
  py::list out;
  for (const Face& f : b.faces()) {
    py::list loops;
    for (const auto& l : f.loops) loops.append(py::cast(l));
    out.append(loops);
  }
  return out;
}

PyBody plain(Body b) { return PyBody{std::move(b), SmoothSurface()}; }

PyBody moved(const PyBody& b, const Transform& t) {
  Body out = [&] {
    py::gil_scoped_release release;
    return b.body.transformed(t);
  }();
  return PyBody{std::move(out), b.surface.transformed(t)};
}

std::pair<double, double> z_range(const py::handle& z) {
  const auto v = z.cast<std::vector<double>>();
  if (v.size() != 2) throw InvalidInput("z: expected (z0, z1)");
  return {v[0], v[1]};
}

Polygon2 polygon_of(const py::handle& value, const char* what) {
  const Doubles a = matrix_of(value, 2, what);
  Polygon2 out;
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) out.emplace_back(r(i, 0), r(i, 1));
  return out;
}

double tolerance_or_default(const std::optional<double>& tolerance, double radius) {
  // 1 % of the radius unless given: about 22 sides for a cylinder.
  return tolerance ? *tolerance : 0.01 * std::abs(radius);
}

std::vector<Body> bodies_of(const py::handle& value) {
  if (py::isinstance<PyBody>(value)) return {value.cast<const PyBody&>().body};
  if (py::isinstance<PyScene>(value)) {
    std::vector<Body> out;
    for (const SceneBody* b : value.cast<const PyScene&>().scene.visible_bodies()) out.push_back(b->body);
    return out;
  }
  std::vector<Body> out;
  for (const py::handle b : value) out.push_back(b.cast<const PyBody&>().body);
  return out;
}

std::vector<PyBody> wrap(const std::vector<Body>& bodies) {
  std::vector<PyBody> out;
  for (const Body& b : bodies) out.push_back(plain(b));
  return out;
}

// Decomposition in any method of the command but TetGen (AGPL, not linked into the module).
std::vector<PyBody> decompose_body(const PyBody& b, const std::string& method,
                                   std::optional<double> tolerance, bool merge, int threads,
                                   py::object progress) {
  if (method != "planes" && method != "float" && method != "cgal" && method != "tetgen")
    throw InvalidInput("unknown method '" + method + "' (expected planes, float, cgal)");
  if (method == "tetgen")
    throw InvalidInput(
        "decompose: method 'tetgen' is not in the Python module (TetGen is AGPL-3.0; use the "
        "hedra command)");
  if (tolerance && method != "float")
    throw InvalidInput("decompose: 'tolerance' applies to method 'float' only");
  DecomposeOptions options;
  options.threads = threads;
  options.merge = merge;
  std::optional<py::error_already_set> error;
  // Progress: the callable (return False to cancel) and Ctrl-C, both with the GIL held.
  options.progress = [&](int done, int open) {
    py::gil_scoped_acquire acquire;
    if (PyErr_CheckSignals() != 0) {
      error.emplace();
      return false;
    }
    if (progress.is_none()) return true;
    try {
      const py::object r = progress(done, open);
      if (!r.is_none() && !r.cast<bool>()) return false;
    } catch (py::error_already_set& e) {
      error.emplace(std::move(e));
      return false;
    }
    return true;
  };
  Decomposition d;
  try {
    py::gil_scoped_release release;
    if (method == "planes") d = decompose(b.body, options);
    if (method == "float") d = decompose_float(b.body, tolerance ? *tolerance : 1e-9, options);
    if (method == "cgal") d = decompose_cgal(b.body);
    if (merge && method == "cgal") d.pieces = merge_convex(d.pieces, &d.merges);
  } catch (const DecompositionCancelled&) {
    if (error) throw *error;
    throw;  // hedra.Cancelled
  }
  return wrap(d.pieces);
}

// Parts of each segment inside (or outside) the bodies: the command's `hedra clip`, rows
// x1 y1 z1 x2 y2 z2 and the 0-based row index.
py::array_t<double> clip_segments(const py::handle& bodies_value, const py::handle& segments_value,
                                  bool outside) {
  const std::vector<Body> bodies = bodies_of(bodies_value);
  const Doubles seg = matrix_of(segments_value, 6, "segments");
  std::vector<std::pair<Vec3, Vec3>> segments(static_cast<size_t>(seg.shape(0)));
  {
    auto r = seg.unchecked<2>();
    for (py::ssize_t i = 0; i < seg.shape(0); ++i) {
      for (int k = 0; k < 6; ++k)
        if (!std::isfinite(r(i, k)) || std::abs(r(i, k)) > kMaxAbsCoordinate)
          throw InvalidInput("segments: row " + std::to_string(i) +
                             ": coordinates must be finite and within ±1e101");
      segments[static_cast<size_t>(i)] = {Vec3(r(i, 0), r(i, 1), r(i, 2)), Vec3(r(i, 3), r(i, 4), r(i, 5))};
    }
  }
  std::vector<double> out;
  {
    py::gil_scoped_release release;
    // As the command: convex bodies through Cyrus–Beck, non-convex ones directly against
    // their triangles (no decomposition).
    const SolidClipper solid(bodies);
    // End points as the command writes them: exact crossings rounded once (end_point).
    auto emit = [&](size_t i, const Vec3& a, const Vec3& b) {
      out.insert(out.end(), {a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), static_cast<double>(i)});
    };
    if (!outside && solid.convex_count() == 1 && solid.polyhedra().empty()) {
      const ConvexClipper& clipper = solid.convex()[0];
      SegmentArrays batch;
      batch.reserve(segments.size());
      for (const auto& s : segments) batch.push_back(s.first, s.second);
      BatchClipResult result;
      clip_batch(clipper, batch, result);
      for (size_t i = 0; i < segments.size(); ++i) {
        if (!result.visible(i)) continue;
        const ClipPart part = result.part(i);
        const auto& [p1, p2] = segments[i];
        emit(i, end_point(clipper, part.start, p1, p2), end_point(clipper, part.end, p1, p2));
      }
    } else {
      for (size_t i = 0; i < segments.size(); ++i) {
        const auto& [p1, p2] = segments[i];
        const auto parts = outside ? solid.clip_outside(p1, p2) : solid.clip(p1, p2);
        for (const ClipPart& p : parts)
          emit(i, solid.end_point(p.start, p1, p2), solid.end_point(p.end, p1, p2));
      }
    }
  }
  return rows_array(out, 7);
}

}  // namespace

void bind_body(py::module_& m) {
  py::class_<PyBody> body(m, "Body",
                          "A closed polyhedron with planar polygonal faces (holes allowed), its "
                          "inner normals and body matrix. Immutable value.");
  body
      .def(py::init([](const py::handle& vertices, const py::handle& faces,
                       std::optional<double> planarity_tolerance) {
             std::vector<Vec3> v = points_of(vertices, "vertices");
             std::vector<Face> f = faces_of(faces);
             BodyOptions options;
             if (planarity_tolerance) options.planarity_tolerance = *planarity_tolerance;
             py::gil_scoped_release release;
             return PyBody{Body(std::move(v), std::move(f), options), SmoothSurface()};
           }),
           py::arg("vertices"), py::arg("faces"), py::arg("planarity_tolerance") = py::none(),
           "Body from an (m, 3) array of vertices and a list of faces (vertex indices, outer "
           "ring counter-clockwise from outside; a face with holes is a list of loops).")
      .def_static(
          "from_triangles",
          [](const py::handle& vertices, const py::handle& triangles, double coplanar_tolerance) {
            PolygonSoup soup;
            soup.vertices = points_of(vertices, "vertices");
            for (const Face& f : faces_of(triangles)) soup.polygons.push_back(f.loops[0]);
            MergeOptions options;
            options.coplanar_tolerance = coplanar_tolerance;
            std::vector<Body> bodies;
            {
              py::gil_scoped_release release;
              bodies = bodies_from_soup(soup, options);
            }
            if (bodies.size() != 1)
              throw InvalidInput("from_triangles: the triangles form " + std::to_string(bodies.size()) +
                                 " separate bodies, expected one");
            return plain(bodies[0]);
          },
          py::arg("vertices"), py::arg("triangles"), py::arg("coplanar_tolerance") = 0.0,
          "Body from a triangle mesh: coplanar neighbours merged into polygonal faces.")
      .def_property_readonly("volume", [](const PyBody& b) { return b.body.volume(); })
      .def_property_readonly("area", [](const PyBody& b) { return b.body.area(); })
      .def_property_readonly("has_exact_solid", [](const PyBody& b) { return b.body.has_exact_solid(); },
                             "True for a Boolean's result and for a body with exactly planar faces moved "
                             "by an affine map: it keeps the exact solid its vertices round.")
      .def_property_readonly("is_convex", [](const PyBody& b) { return is_convex(b.body); },
                             "Exact convexity test.")
      .def_property_readonly("nonconvex_faces",
                             [](const PyBody& b) { return convexity(b.body).nonconvex_faces; })
      .def_property_readonly(
          "matrix",
          [](const PyBody& b) {
            const BodyMatrix& v = b.body.matrix();
            py::array_t<double> out({py::ssize_t{4}, static_cast<py::ssize_t>(v.cols())});
            auto w = out.mutable_unchecked<2>();
            for (int r = 0; r < 4; ++r)
              for (py::ssize_t c = 0; c < v.cols(); ++c) w(r, c) = v(r, c);
            return out;
          },
          "(4, n) body matrix: column j = (a, b, c, d) of face j, inner normals (a copy).")
      .def_property_readonly("vertices", [](const PyBody& b) { return points_array(b.body.vertices()); },
                             "(m, 3) vertices (a copy).")
      .def_property_readonly("faces", [](const PyBody& b) { return faces_list(b.body); },
                             "Per face an int array (outer ring), or a list of loops when it has holes.")
      .def_property_readonly("triangles",
                             [](const PyBody& b) {
                               const auto& t = b.body.triangles();
                               py::array_t<int> out({static_cast<py::ssize_t>(t.size()), py::ssize_t{3}});
                               auto w = out.mutable_unchecked<2>();
                               for (size_t i = 0; i < t.size(); ++i)
                                 for (int k = 0; k < 3; ++k) w(static_cast<py::ssize_t>(i), k) = t[i].v[static_cast<size_t>(k)];
                               return out;
                             })
      .def_property_readonly("face_count", [](const PyBody& b) { return b.body.face_count(); })
      .def_property_readonly("vertex_count", [](const PyBody& b) { return b.body.vertex_count(); })
      .def_property_readonly("edge_count", [](const PyBody& b) { return b.body.edge_count(); })
      .def_property_readonly("centroid", [](const PyBody& b) { return points_array({b.body.centroid()}).attr("reshape")(3); })
      .def_property_readonly("bbox", [](const PyBody& b) {
        return points_array({b.body.bbox().min(), b.body.bbox().max()});
      }, "(2, 3): lowest and highest corner.")
      .def_property_readonly("is_smooth", [](const PyBody& b) { return b.surface.is_smooth(); },
                             "Carries an analytic surface (sphere, cylinder, cone) for smooth shading.")
      .def("classify",
           [](const PyBody& b, const py::handle& p) {
             const Location l = b.body.classify(vec3(p, "point"));
             return l == Location::Inside ? "inside" : l == Location::OnBoundary ? "boundary" : "outside";
           },
           py::arg("point"), "Exact: 'inside', 'boundary' or 'outside'.")
      .def("translated", [](const PyBody& b, const py::handle& v) {
        return moved(b, Transform::translation(vec3(v, "translated")));
      }, py::arg("v"))
      .def("rotated",
           [](const PyBody& b, const py::handle& axis, double degrees, const py::handle& about) {
             return moved(b, Transform::rotation(vec3(axis, "axis"), degrees, vec3(about, "about")));
           },
           py::arg("axis"), py::arg("degrees"), py::arg("about") = py::make_tuple(0, 0, 0),
           "Rotation by `degrees` (right-handed) about the axis through `about`.")
      .def("scaled",
           [](const PyBody& b, const py::handle& k, const py::handle& about) {
             const Vec3 factors = PyNumber_Check(k.ptr()) && !py::isinstance<py::sequence>(k)
                                      ? Vec3::Constant(k.cast<double>())
                                      : vec3(k, "scaled");
             return moved(b, Transform::scaling(factors, vec3(about, "about")));
           },
           py::arg("k"), py::arg("about") = py::make_tuple(0, 0, 0),
           "Scaling by a number or (kx, ky, kz) about a point; negative factors reflect.")
      .def("transformed",
           [](const PyBody& b, const py::handle& t) {
             const Doubles a = matrix_of(t, 4, "transformed");
             if (a.shape(0) != 4) throw InvalidInput("transformed: expected a (4, 4) matrix");
             Mat4 mat;
             for (int r = 0; r < 4; ++r)
               for (int c = 0; c < 4; ++c) mat(r, c) = a.at(r, c);
             return moved(b, Transform(mat));
           },
           py::arg("matrix"),
           "Homogeneous 4x4 transformation in hedra's row-vector convention: (x, y, z, 1) @ M, "
           "translation in the last row (as hedra::Transform).")
      .def("__repr__",
           [](const PyBody& b) {
             char buf[160];
             std::snprintf(buf, sizeof buf, "hedra.Body(%d vertices, %d faces, volume %.6g)",
                           b.body.vertex_count(), b.body.face_count(), b.body.volume());
             return std::string(buf);
           })
      .def(py::pickle(
          [](const PyBody& b) {
            // Vertices as their bytes (exact), faces as loops; rebuilt and validated on load.
            const auto& v = b.body.vertices();
            std::string bytes(v.size() * 3 * sizeof(double), '\0');
            for (size_t i = 0; i < v.size(); ++i)
              std::memcpy(&bytes[i * 3 * sizeof(double)], v[i].data(), 3 * sizeof(double));
            // Version 2: and the exact solid it rounds (Body::exact_solid_bytes(), empty if
            // none), so that a worker decides on it as this process does.
            return py::make_tuple(2, py::bytes(bytes), faces_plain(b.body), py::bytes(b.body.exact_solid_bytes()));
          },
          [](const py::tuple& state) {
            const int version = state.size() >= 1 ? state[0].cast<int>() : 0;
            if (!((version == 1 && state.size() == 3) || (version == 2 && state.size() == 4)))
              throw InvalidInput("Body: unknown pickle state");
            const std::string bytes = state[1].cast<std::string>();
            std::vector<Vec3> v(bytes.size() / (3 * sizeof(double)));
            for (size_t i = 0; i < v.size(); ++i)
              std::memcpy(v[i].data(), &bytes[i * 3 * sizeof(double)], 3 * sizeof(double));
            Body body(std::move(v), faces_of(state[2]));
            if (version == 2) body = body.with_exact_solid_bytes(state[3].cast<std::string>());
            return PyBody{std::move(body), SmoothSurface()};
          }));

  // Primitives.
  m.def("box", [](const py::handle& lo, const py::handle& hi) { return plain(box(vec3(lo, "lo"), vec3(hi, "hi"))); },
        py::arg("lo"), py::arg("hi"), "Axis-aligned box.");
  m.def("prism",
        [](const py::handle& outline, const py::handle& z, const py::handle& holes) {
          const auto [z0, z1] = z_range(z);
          std::vector<Polygon2> h;
          for (const py::handle hole : holes) h.push_back(polygon_of(hole, "holes"));
          return plain(prism(polygon_of(outline, "outline"), z0, z1, h));
        },
        py::arg("outline"), py::arg("z") = py::make_tuple(0, 1), py::arg("holes") = py::list(),
        "A simple polygon (with optional holes) extruded from z0 to z1.");
  m.def("pyramid",
        [](const py::handle& base, double z0, const py::handle& apex) {
          return plain(pyramid(polygon_of(base, "base"), z0, vec3(apex, "apex")));
        },
        py::arg("base"), py::arg("z0"), py::arg("apex"));
  m.def("frustum",
        [](const py::handle& base, double z0, const py::handle& apex, double z1) {
          return plain(frustum(polygon_of(base, "base"), z0, vec3(apex, "apex"), z1));
        },
        py::arg("base"), py::arg("z0"), py::arg("apex"), py::arg("z1"),
        "The pyramid over `base` at z0 with apex `apex`, cut at z1 between them; keeps the exact "
        "frustum where its top corners are rounded (has_exact_solid).");
  m.def("regular_prism",
        [](int n, double radius, const py::handle& z) {
          const auto [z0, z1] = z_range(z);
          return plain(regular_prism(n, radius, z0, z1));
        },
        py::arg("n"), py::arg("radius"), py::arg("z") = py::make_tuple(0, 1));
  m.def("cylinder",
        [](double radius, const py::handle& z, std::optional<double> tolerance) {
          const auto [z0, z1] = z_range(z);
          return PyBody{cylinder(radius, z0, z1, tolerance_or_default(tolerance, radius)),
                        SmoothSurface::cylinder(radius, z0, z1)};
        },
        py::arg("radius"), py::arg("z") = py::make_tuple(0, 1), py::arg("tolerance") = py::none(),
        "Cylinder about the z axis; chordal tolerance (default 1 % of the radius).");
  m.def("cone",
        [](double radius, const py::handle& z, std::optional<double> tolerance) {
          const auto [z0, z1] = z_range(z);
          return PyBody{cone(radius, z0, z1, tolerance_or_default(tolerance, radius)),
                        SmoothSurface::cone(radius, z0, z1)};
        },
        py::arg("radius"), py::arg("z") = py::make_tuple(0, 1), py::arg("tolerance") = py::none(),
        "Cone: base circle at z0, apex (0, 0, z1); chordal tolerance (default 1 % of the radius).");
  m.def("sphere",
        [](const py::handle& center, double radius, std::optional<double> tolerance) {
          const Vec3 c = vec3(center, "center");
          return PyBody{sphere(c, radius, tolerance_or_default(tolerance, radius)),
                        SmoothSurface::sphere(c, radius)};
        },
        py::arg("center"), py::arg("radius"), py::arg("tolerance") = py::none(),
        "Sphere; chordal tolerance (default 1 % of the radius).");

  // Booleans (exact, CGAL corefinement); empty results are None.
  m.def("unite", [](const PyBody& a, const PyBody& b) { return plain(unite(a.body, b.body)); },
        py::arg("a"), py::arg("b"), py::call_guard<py::gil_scoped_release>());
  m.def("subtract",
        [](const PyBody& a, const PyBody& b) -> std::optional<PyBody> {
          auto r = subtract(a.body, b.body);
          if (!r) return std::nullopt;
          return plain(*r);
        },
        py::arg("a"), py::arg("b"), py::call_guard<py::gil_scoped_release>());
  m.def("intersect",
        [](const PyBody& a, const PyBody& b) -> std::optional<PyBody> {
          auto r = intersect(a.body, b.body);
          if (!r) return std::nullopt;
          return plain(*r);
        },
        py::arg("a"), py::arg("b"), py::call_guard<py::gil_scoped_release>());

  m.def(
      "exact_volume_sign",
      [](const std::vector<std::pair<int, PyBody>>& terms) {
        std::vector<std::pair<int, Body>> t;
        for (const auto& [k, b] : terms) t.emplace_back(k, b.body);
        py::gil_scoped_release release;
        return static_cast<int>(exact_volume_sign(t));
      },
      py::arg("terms"),
      "Sign (-1, 0, 1) of the sum of k * volume over [(k, body), ...], exactly: a Boolean's "
      "result counts with its exact solid. V(A - B) + V(A & B) - V(A) gives 0.");
  m.def("decompose", &decompose_body, py::arg("body"), py::arg("method") = "planes",
        py::arg("tolerance") = py::none(), py::arg("merge") = false, py::arg("threads") = 0,
        py::arg("progress") = py::none(),
        "Convex pieces: 'planes' (exact, default), 'float' (doubles, relative tolerance), "
        "'cgal' (CGAL Nef). progress(done, open) returning False cancels.");
  m.def("clip", &clip_segments, py::arg("body"), py::arg("segments"), py::arg("outside") = false,
        "Clips (n, 6) segments against a body (or a list of bodies, or a scene's bodies): "
        "(m, 7) parts, 7th column the segment's row.");
  m.def("encode_png",
        [](const py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>& rgb) {
          if (rgb.ndim() != 3 || rgb.shape(2) != 3) throw InvalidInput("encode_png: expected an (h, w, 3) uint8 array");
          std::vector<std::uint8_t> pixels(rgb.data(), rgb.data() + rgb.size());
          return py::bytes(io::encode_png(static_cast<int>(rgb.shape(1)), static_cast<int>(rgb.shape(0)), pixels));
        },
        py::arg("rgb"));
}

}  // namespace hedra::python
