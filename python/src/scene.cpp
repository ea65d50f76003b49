// hedra.Scene, Camera, Light, Material; reading and writing; hidden lines, shadows, sun studies
// and rendering. Long computations run on a copy of the scene (bodies are shared, immutable)
// with the GIL released, so other Python threads run meanwhile.
#include <pybind11/stl.h>
#include <pybind11/stl_bind.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <optional>

#include "common.h"
#include "hedra/io/report_json.h"

PYBIND11_MAKE_OPAQUE(std::vector<hedra::Light>)

namespace hedra::python {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

py::tuple tuple3(const Vec3& v) { return py::make_tuple(v.x(), v.y(), v.z()); }

const char* light_type_name(Light::Type t) {
  switch (t) {
    case Light::Type::Directional: return "directional";
    case Light::Type::Point: return "point";
    case Light::Type::Spot: return "spot";
    case Light::Type::Sun: return "sun";
  }
  return "directional";
}

// The command's reading of a file (cli/info.cpp load_scene): a scene file as it is, a mesh file
// as a scene of its bodies ("stem", or "stem#i" for several) seen parallel from (1, 2, 1.5)
// towards the origin under a directional light from the same side.
PyScene read_any(const std::string& path, double coplanar_tolerance, std::optional<double> planarity_tolerance) {
  PyScene out;
  out.source = path;
  if (io::is_scene_path(path)) {
    out.scene = io::read_scene(path);
    return out;
  }
  io::ReadOptions options;
  options.merge.coplanar_tolerance = coplanar_tolerance;
  if (planarity_tolerance) options.merge.planarity_tolerance = *planarity_tolerance;
  const std::vector<Body> bodies = io::read_bodies(path, options);
  const std::string stem = std::filesystem::path(path).stem().string();
  for (size_t i = 0; i < bodies.size(); ++i)
    out.scene.add(bodies.size() == 1 ? stem : stem + "#" + std::to_string(i), bodies[i]);
  out.scene.camera = Camera::parallel({-1, -2, -1.5}, {0, 0, 1});
  out.scene.lights.push_back(Light::directional({-1, -1.5, -3}, 0.9));
  return out;
}

// A str or os.PathLike as a file name.
std::string path_of(const py::object& path) {
  return py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
}

void write_any(const py::handle& what, const py::object& path_like, bool stl_ascii) {
  const std::string path = path_of(path_like);
  if (py::isinstance<PyBody>(what)) {
    const PyBody& b = what.cast<const PyBody&>();
    if (io::is_scene_path(path)) {
      Scene s;
      s.add(std::filesystem::path(path).stem().string(), b.body);
      io::write_scene(s, path);
    } else {
      io::WriteOptions o;
      o.stl_ascii = stl_ascii;
      io::write_bodies({b.body}, path, o);
    }
    return;
  }
  const PyScene& s = what.cast<const PyScene&>();
  if (io::is_scene_path(path)) {
    io::write_scene(s.scene, path);
    return;
  }
  std::vector<Body> bodies;
  for (const SceneBody* b : s.scene.visible_bodies()) bodies.push_back(b->body);
  io::WriteOptions o;
  o.stl_ascii = stl_ascii;
  io::write_bodies(bodies, path, o);
}

// ---- pickling: every field as doubles/ints/strings, so states round-trip exactly ----

py::tuple material_state(const Material& m) {
  return py::make_tuple(tuple3(m.color), m.ka, m.kd, m.ks, m.shininess);
}
Material material_from(const py::tuple& t) {
  Material m;
  m.color = vec3(t[0], "color");
  m.ka = t[1].cast<double>();
  m.kd = t[2].cast<double>();
  m.ks = t[3].cast<double>();
  m.shininess = t[4].cast<double>();
  return m;
}
py::tuple camera_state(const Camera& c) {
  return py::make_tuple(static_cast<int>(c.projection), tuple3(c.direction), tuple3(c.eye),
                        tuple3(c.target), c.fov_deg, tuple3(c.up), c.width, c.height);
}
Camera camera_from(const py::tuple& t) {
  Camera c;
  c.projection = static_cast<Camera::Projection>(t[0].cast<int>());
  c.direction = vec3(t[1], "direction");
  c.eye = vec3(t[2], "eye");
  c.target = vec3(t[3], "target");
  c.fov_deg = t[4].cast<double>();
  c.up = vec3(t[5], "up");
  c.width = t[6].cast<int>();
  c.height = t[7].cast<int>();
  return c;
}
py::tuple light_state(const Light& l) {
  const UtcTime& u = l.time;
  return py::make_tuple(static_cast<int>(l.type), tuple3(l.direction), tuple3(l.position),
                        l.intensity, tuple3(l.color), l.cone_deg, l.falloff, l.latitude,
                        l.longitude,
                        py::make_tuple(u.year, u.month, u.day, u.hour, u.minute, u.second));
}
Light light_from(const py::tuple& t) {
  Light l;
  l.type = static_cast<Light::Type>(t[0].cast<int>());
  l.direction = vec3(t[1], "direction");
  l.position = vec3(t[2], "position");
  l.intensity = t[3].cast<double>();
  l.color = vec3(t[4], "color");
  l.cone_deg = t[5].cast<double>();
  l.falloff = t[6].cast<double>();
  l.latitude = t[7].cast<double>();
  l.longitude = t[8].cast<double>();
  const py::tuple u = t[9].cast<py::tuple>();
  l.time.year = u[0].cast<int>();
  l.time.month = u[1].cast<int>();
  l.time.day = u[2].cast<int>();
  l.time.hour = u[3].cast<int>();
  l.time.minute = u[4].cast<int>();
  l.time.second = u[5].cast<double>();
  return l;
}

py::tuple scene_state(const PyScene& s) {
  py::list bodies;
  for (const SceneBody& b : s.scene.bodies())
    bodies.append(py::make_tuple(b.name, py::cast(PyBody{b.body, SmoothSurface()}).attr("__getstate__")(),
                                 material_state(b.material), b.hidden, b.lod_note,
                                 py::cast(b.surface.state())));
  py::list lights;
  for (const Light& l : s.scene.lights) lights.append(light_state(l));
  return py::make_tuple(1, bodies, camera_state(s.scene.camera), lights,
                        tuple3(s.scene.image.background), s.source);
}

PyScene scene_from(const py::tuple& t) {
  if (t.size() != 6 || t[0].cast<int>() != 1) throw InvalidInput("Scene: unknown pickle state");
  PyScene s;
  py::object body_type = py::module_::import("hedra._hedra").attr("Body");
  for (const py::handle item : t[1].cast<py::list>()) {
    const py::tuple b = item.cast<py::tuple>();
    py::object body = body_type.attr("__new__")(body_type);
    body.attr("__setstate__")(b[1]);
    SceneBody& added = s.scene.add(b[0].cast<std::string>(), body.cast<const PyBody&>().body,
                                   material_from(b[2].cast<py::tuple>()));
    added.hidden = b[3].cast<bool>();
    added.lod_note = b[4].cast<std::string>();
    // The analytic surface (hidden-line outlines, smooth shading); absent in older pickles.
    if (b.size() > 5) added.surface = SmoothSurface::from_state(b[5].cast<std::vector<double>>());
  }
  s.scene.camera = camera_from(t[2].cast<py::tuple>());
  for (const py::handle l : t[3].cast<py::list>()) s.scene.lights.push_back(light_from(l.cast<py::tuple>()));
  s.scene.image.background = vec3(t[4], "background");
  s.source = t[5].cast<std::string>();
  return s;
}

py::tuple time_state(const UtcTime& u) {
  return py::make_tuple(u.year, u.month, u.day, u.hour, u.minute, u.second);
}
UtcTime time_from(const py::handle& h) {
  const py::tuple u = h.cast<py::tuple>();
  UtcTime t;
  t.year = u[0].cast<int>();
  t.month = u[1].cast<int>();
  t.day = u[2].cast<int>();
  t.hour = u[3].cast<int>();
  t.minute = u[4].cast<int>();
  t.second = u[5].cast<double>();
  return t;
}

// Doubles as their bytes: exact.
py::bytes doubles_bytes(const double* p, size_t n) {
  return py::bytes(reinterpret_cast<const char*>(p), n * sizeof(double));
}
std::vector<double> doubles_from(const py::handle& h) {
  const std::string b = h.cast<std::string>();
  std::vector<double> v(b.size() / sizeof(double));
  if (!v.empty()) std::memcpy(v.data(), b.data(), v.size() * sizeof(double));
  return v;
}

std::vector<Light> lights_of(const py::handle& value) {
  std::vector<Light> out;
  for (const py::handle l : value) out.push_back(l.cast<Light>());
  return out;
}

// ---- results ----

struct PyHiddenLines {
  HlrResult result;
  double ms = 0;
  int width = 800, height = 600;
  Vec3 background = Vec3(1, 1, 1);
  bool hidden = false;
  RasterView view;  // the renderer's framing of the scene (svg(fit=False))
};

// `progress=`: a Python callable f(done) (done from 0 to 1; returning False cancels) and Ctrl-C,
// both seen with the GIL taken on the calling thread; what the callable raised is raised again
// after the work stopped. Use: callback() in the options, then rethrow() when Cancelled.
struct PyProgress {
  py::object callable;
  std::optional<py::error_already_set> error;
  ProgressCallback callback() {
    return [this](double done) {
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {
        error.emplace();
        return false;
      }
      if (callable.is_none()) return true;
      try {
        const py::object r = callable(done);
        if (!r.is_none() && !r.cast<bool>()) return false;
      } catch (py::error_already_set& e) {
        error.emplace(std::move(e));
        return false;
      }
      return true;
    };
  }
  [[noreturn]] void rethrow() {
    if (error) throw *error;
    throw;  // hedra.Cancelled
  }
};

py::array_t<double> segments_of(const std::vector<HlrSegment>& list, LineKind kind) {
  std::vector<double> flat;
  for (const HlrSegment& s : list)
    if (s.kind == kind) flat.insert(flat.end(), {s.a.x(), s.a.y(), s.a.z(), s.b.x(), s.b.y(), s.b.z()});
  return rows_array(flat, 6);
}

std::string svg_of(const PyHiddenLines& h, std::optional<bool> hidden, const std::string& title,
                   bool fit) {
  SvgStyle style;
  if (!fit) style.view = h.view;
  style.width = h.width;
  style.height = h.height;
  style.background = h.background;
  style.hidden = hidden.value_or(h.hidden);
  style.title = title;
  return hidden_lines_svg(h.result, style);
}

struct PyShadows {
  Scene scene;
  std::string source;
  ShadowResult result;
  bool visible_parts = false;
  double ms = 0;
};

py::list polygons_of(const std::vector<ShadowPolygon>& polys) {
  py::list out;
  for (const ShadowPolygon& p : polys) {
    py::list holes;
    for (const Polygon3& h : p.holes) holes.append(points_array(h));
    out.append(py::make_tuple(points_array(p.outer), holes));
  }
  return out;
}

py::dict face_record(const PyShadows& s, const FaceShadow& fs) {
  py::dict d;
  d["body"] = s.scene.bodies()[static_cast<size_t>(fs.body)].name;
  d["face"] = fs.face;
  d["area"] = fs.area;
  d["self_shadowed"] = fs.self_shadowed();
  d["grazing"] = fs.grazing();
  d["visible"] = fs.visible;
  d["shadow_area"] = fs.shadow_area;
  d["lit_fraction"] = fs.lit_fraction();
  d["polygons"] = polygons_of(fs.polygons);
  if (s.visible_parts) {
    d["visible_shadow_area"] = fs.visible_shadow_area;
    d["visible_polygons"] = polygons_of(fs.visible_polygons);
  }
  return d;
}

int body_index(const Scene& scene, const std::string& name) {
  for (size_t b = 0; b < scene.bodies().size(); ++b)
    if (scene.bodies()[b].name == name) return static_cast<int>(b);
  throw InvalidInput("no body named '" + name + "'");
}

struct PySunStudy {
  Scene scene;
  SunStudyOptions options;
  SunStudy study;
};

// "hh:mm" on the date of `date`, or a full ISO 8601 UTC time (as `hedra shadows --sun-hours`).
UtcTime time_of(const std::string& text, const UtcTime* date) {
  if (text.size() == 5 && text[2] == ':' && date != nullptr) {
    char iso[40];
    std::snprintf(iso, sizeof iso, "%04d-%02d-%02dT%s:00Z", date->year, date->month, date->day,
                  text.c_str());
    return UtcTime::parse(iso);
  }
  return UtcTime::parse(text);
}

const Light* scene_sun(const Scene& scene) {
  for (const Light& l : scene.lights)
    if (l.type == Light::Type::Sun) return &l;
  return nullptr;
}

PySunStudy run_sun_study(const PyScene& s, const std::string& start, const std::string& end,
                         double step_minutes, std::optional<double> latitude,
                         std::optional<double> longitude, const py::object& grid, int threads,
                         const std::string& grid_body, int grid_face, double grid_spacing,
                         int first_step, int step_count) {
  const Light* sun = scene_sun(s.scene);
  SunStudyOptions o;
  if ((!latitude || !longitude) && sun == nullptr)
    throw InvalidInput((s.source.empty() ? std::string() : s.source + ": ") +
                       "a sun study needs a sun light in the scene or latitude and longitude");
  o.latitude = latitude ? *latitude : sun->latitude;
  o.longitude = longitude ? *longitude : sun->longitude;
  o.start = time_of(start, sun ? &sun->time : nullptr);
  o.end = time_of(end, sun ? &sun->time : nullptr);
  o.step_minutes = step_minutes;
  o.threads = threads;
  o.first_step = first_step;
  o.step_count = step_count;
  if (!grid.is_none()) {
    const py::tuple g = grid.cast<py::tuple>();
    if (g.size() != 3) throw InvalidInput("grid: expected (body, face, spacing)");
    o.grid_body = g[0].cast<std::string>();
    o.grid_face = g[1].cast<int>();
    o.grid_spacing = g[2].cast<double>();
  } else if (!grid_body.empty()) {
    o.grid_body = grid_body;
    o.grid_face = grid_face;
    o.grid_spacing = grid_spacing;
  }
  PySunStudy out{s.scene, o, {}};
  py::gil_scoped_release release;
  try {
    out.study = sun_study(out.scene, o);
  } catch (const InvalidInput& e) {
    rethrow_with_source(s, e);
  }
  return out;
}

// Joins slices (hedra.sun_study with first_step/step_count) into the whole study; the scene
// and the schedule are the first part's.
PySunStudy combine_studies(const std::vector<const PySunStudy*>& parts) {
  if (parts.empty()) throw InvalidInput("combine_sun_studies: no parts");
  PySunStudy out{parts[0]->scene, parts[0]->options, {}};
  out.options.first_step = 0;
  out.options.step_count = -1;
  std::vector<SunStudy> studies;
  for (const PySunStudy* p : parts) studies.push_back(p->study);
  py::gil_scoped_release release;
  out.study = combine_sun_studies(studies, out.options);
  return out;
}

py::array_t<double> doubles_array(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(double));
  return a;
}

Shading shading_of(const std::string& name) {
  if (name == "flat") return Shading::Flat;
  if (name == "gouraud") return Shading::Gouraud;
  if (name == "phong") return Shading::Phong;
  throw InvalidInput("shading '" + name + "': expected flat, gouraud or phong");
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<Material>(m, "Material", "Phong material: colour, ka, kd, ks, shininess.")
      .def(py::init([](const py::handle& color, double ka, double kd, double ks, double shininess) {
             Material mat;
             mat.color = vec3(color, "color");
             mat.ka = ka;
             mat.kd = kd;
             mat.ks = ks;
             mat.shininess = shininess;
             mat.validate();
             return mat;
           }),
           py::arg("color") = py::make_tuple(0.8, 0.8, 0.8), py::arg("ka") = 0.2,
           py::arg("kd") = 0.7, py::arg("ks") = 0.2, py::arg("shininess") = 20.0)
      .def_property("color", [](const Material& x) { return tuple3(x.color); },
                    [](Material& x, const py::handle& v) { x.color = vec3(v, "color"); })
      .def_readwrite("ka", &Material::ka)
      .def_readwrite("kd", &Material::kd)
      .def_readwrite("ks", &Material::ks)
      .def_readwrite("shininess", &Material::shininess)
      .def("__eq__", [](const Material& a, const Material& b) { return a == b; })
      .def(py::pickle([](const Material& x) { return material_state(x); },
                      [](const py::tuple& t) { return material_from(t); }));

  py::class_<Camera>(m, "Camera", "Parallel or perspective camera with an image size.")
      .def(py::init<>())
      .def_static("parallel",
                  [](const py::handle& direction, const py::handle& up) {
                    Camera c = Camera::parallel(vec3(direction, "direction"), vec3(up, "up"));
                    c.validate();
                    return c;
                  },
                  py::arg("direction"), py::arg("up") = py::make_tuple(0, 0, 1))
      .def_static("perspective",
                  [](const py::handle& eye, const py::handle& target, double fov_deg, const py::handle& up) {
                    Camera c = Camera::perspective(vec3(eye, "eye"), vec3(target, "target"), fov_deg, vec3(up, "up"));
                    c.validate();
                    return c;
                  },
                  py::arg("eye"), py::arg("target"), py::arg("fov_deg") = 45.0,
                  py::arg("up") = py::make_tuple(0, 0, 1))
      .def_property_readonly("projection", [](const Camera& c) {
        return c.projection == Camera::Projection::Parallel ? "parallel" : "perspective";
      })
      .def_property("direction", [](const Camera& c) { return tuple3(c.direction); },
                    [](Camera& c, const py::handle& v) { c.direction = vec3(v, "direction"); })
      .def_property("eye", [](const Camera& c) { return tuple3(c.eye); },
                    [](Camera& c, const py::handle& v) { c.eye = vec3(v, "eye"); })
      .def_property("target", [](const Camera& c) { return tuple3(c.target); },
                    [](Camera& c, const py::handle& v) { c.target = vec3(v, "target"); })
      .def_property("up", [](const Camera& c) { return tuple3(c.up); },
                    [](Camera& c, const py::handle& v) { c.up = vec3(v, "up"); })
      .def_readwrite("fov_deg", &Camera::fov_deg)
      .def_readwrite("width", &Camera::width)
      .def_readwrite("height", &Camera::height)
      .def("__repr__", [](const Camera& c) {
        char buf[200];
        if (c.projection == Camera::Projection::Parallel)
          std::snprintf(buf, sizeof buf, "hedra.Camera.parallel((%g, %g, %g)), %dx%d", c.direction.x(),
                        c.direction.y(), c.direction.z(), c.width, c.height);
        else
          std::snprintf(buf, sizeof buf, "hedra.Camera.perspective((%g, %g, %g), (%g, %g, %g), %g), %dx%d",
                        c.eye.x(), c.eye.y(), c.eye.z(), c.target.x(), c.target.y(), c.target.z(),
                        c.fov_deg, c.width, c.height);
        return std::string(buf);
      })
      .def(py::pickle([](const Camera& c) { return camera_state(c); },
                      [](const py::tuple& t) { return camera_from(t); }));

  py::class_<Light>(m, "Light", "Directional, point, spot light or the sun.")
      .def_static("directional",
                  [](const py::handle& d, double intensity) {
                    Light l = Light::directional(vec3(d, "direction"), intensity);
                    l.validate();
                    return l;
                  },
                  py::arg("direction"), py::arg("intensity") = 1.0)
      .def_static("point",
                  [](const py::handle& p, double intensity) {
                    Light l = Light::point(vec3(p, "position"), intensity);
                    l.validate();
                    return l;
                  },
                  py::arg("position"), py::arg("intensity") = 1.0)
      .def_static("spot",
                  [](const py::handle& p, const py::handle& d, double cone_deg, double falloff, double intensity) {
                    Light l = Light::spot(vec3(p, "position"), vec3(d, "direction"), cone_deg, falloff, intensity);
                    l.validate();
                    return l;
                  },
                  py::arg("position"), py::arg("direction"), py::arg("cone_deg") = 30.0,
                  py::arg("falloff") = 1.0, py::arg("intensity") = 1.0)
      .def_static("sun",
                  [](double latitude, double longitude, const std::string& time, double intensity) {
                    return Light::sun(latitude, longitude, UtcTime::parse(time), intensity);
                  },
                  py::arg("latitude"), py::arg("longitude"), py::arg("time"), py::arg("intensity") = 1.0,
                  "The sun at a place (degrees north, east) and a UTC time (ISO 8601, '…Z').")
      .def_property_readonly("type", [](const Light& l) { return light_type_name(l.type); })
      .def_property("direction", [](const Light& l) { return tuple3(l.direction); },
                    [](Light& l, const py::handle& v) { l.direction = vec3(v, "direction"); })
      .def_property("position", [](const Light& l) { return tuple3(l.position); },
                    [](Light& l, const py::handle& v) { l.position = vec3(v, "position"); })
      .def_property("color", [](const Light& l) { return tuple3(l.color); },
                    [](Light& l, const py::handle& v) { l.color = vec3(v, "color"); })
      .def_readwrite("intensity", &Light::intensity)
      .def_readwrite("cone_deg", &Light::cone_deg)
      .def_readwrite("falloff", &Light::falloff)
      .def_readonly("latitude", &Light::latitude)
      .def_readonly("longitude", &Light::longitude)
      .def_property_readonly("time", [](const Light& l) { return l.time.to_string(); })
      .def("__repr__", [](const Light& l) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "hedra.Light(%s, direction (%g, %g, %g), position (%g, %g, %g))",
                      light_type_name(l.type), l.direction.x(), l.direction.y(), l.direction.z(),
                      l.position.x(), l.position.y(), l.position.z());
        return std::string(buf);
      })
      .def(py::pickle([](const Light& l) { return light_state(l); },
                      [](const py::tuple& t) { return light_from(t); }));

  py::bind_vector<std::vector<Light>>(m, "LightList", "The lights of a scene (a live list).")
      .def("__repr__", [](const std::vector<Light>& lights) {
        std::string s = "[";
        for (size_t i = 0; i < lights.size(); ++i)
          s += (i ? ", " : "") + std::string(py::repr(py::cast(lights[i])));
        return s + "]";
      });

  py::class_<PyScene>(m, "Scene", "Named bodies with materials, a camera and lights.")
      .def(py::init<>())
      .def("add",
           [](PyScene& s, const std::string& name, const PyBody& body, const py::object& color,
              const py::object& material, bool hidden) {
             Material mat = material.is_none() ? Material() : material.cast<Material>();
             if (!color.is_none()) mat.color = vec3(color, "color");
             mat.validate();
             SceneBody& added = s.scene.add(name, body.body, mat);
             added.surface = body.surface;
             added.hidden = hidden;
             return body;
           },
           py::arg("name"), py::arg("body"), py::arg("color") = py::none(),
           py::arg("material") = py::none(), py::arg("hidden") = false,
           "Adds a body under a new name (hidden bodies are kept but not drawn or shaded).")
      .def_property_readonly(
          "bodies",
          [](const PyScene& s) {
            py::dict d;
            for (const SceneBody& b : s.scene.bodies()) d[py::str(b.name)] = PyBody{b.body, b.surface};
            return d;
          },
          "name -> Body, every body in order (a new dict; Bodies are immutable values).")
      .def("material", [](const PyScene& s, const std::string& name) { return s.scene.get(name).material; },
           py::arg("name"))
      .def("is_hidden", [](const PyScene& s, const std::string& name) { return s.scene.get(name).hidden; },
           py::arg("name"))
      .def("__len__", [](const PyScene& s) { return s.scene.bodies().size(); })
      .def("__contains__", [](const PyScene& s, const std::string& name) { return s.scene.contains(name); })
      .def("__getitem__", [](const PyScene& s, const std::string& name) {
        if (!s.scene.contains(name)) throw py::key_error(name);
        const SceneBody& b = s.scene.get(name);
        return PyBody{b.body, b.surface};
      })
      .def_property(
          "camera", [](PyScene& s) -> Camera& { return s.scene.camera; },
          [](PyScene& s, const Camera& c) { s.scene.camera = c; }, py::return_value_policy::reference_internal)
      .def_property(
          "lights", [](PyScene& s) -> std::vector<Light>& { return s.scene.lights; },
          [](PyScene& s, const py::handle& v) { s.scene.lights = lights_of(v); },
          py::return_value_policy::reference_internal)
      .def_property("background", [](const PyScene& s) { return tuple3(s.scene.image.background); },
                    [](PyScene& s, const py::handle& v) { s.scene.image.background = vec3(v, "background"); })
      .def_readonly("source", &PyScene::source, "The file it was read from ('' when built in Python).")
      .def("to_json", [](const PyScene& s) { return io::format_scene(s.scene); },
           "The scene file text (bodies as explicit polyhedra).")
      .def("__repr__", [](const PyScene& s) {
        return "hedra.Scene(" + std::to_string(s.scene.bodies().size()) + " bodies, " +
               std::to_string(s.scene.lights.size()) + " lights" +
               (s.source.empty() ? std::string() : ", from " + s.source) + ")";
      })
      .def(py::pickle(&scene_state, &scene_from));

  m.def("demo_scene", [] { return PyScene{demo_scene(), ""}; }, "The scene of `hedra demo`.");
  m.def("read", [](const py::object& path_like, double coplanar_tolerance, std::optional<double> planarity_tolerance) {
    const std::string path = path_of(path_like);
    py::gil_scoped_release release;
    return read_any(path, coplanar_tolerance, planarity_tolerance);
  }, py::arg("path"), py::arg("coplanar_tolerance") = 0.0, py::arg("planarity_tolerance") = py::none(),
  "A scene (.json) or mesh file (OFF, OBJ, STL, PLY) as a Scene, as the command reads it.");
  m.def("write", &write_any, py::arg("what"), py::arg("path"), py::arg("stl_ascii") = false,
        "Writes a Scene or a Body: scene JSON or a mesh file by the extension, atomically.");

  // ---- hidden lines ----
  py::class_<PyHiddenLines>(m, "HiddenLines", "Roberts hidden-line removal result (world coordinates).")
      .def_property_readonly("visible", [](const PyHiddenLines& h) { return segments_of(h.result.visible, LineKind::Edge); },
                             "(k, 6) visible edge segments x1 y1 z1 x2 y2 z2.")
      .def_property_readonly("hidden", [](const PyHiddenLines& h) { return segments_of(h.result.hidden, LineKind::Edge); },
                             "(k, 6) hidden edge segments (with hidden=True).")
      .def_property_readonly("junction", [](const PyHiddenLines& h) { return segments_of(h.result.visible, LineKind::Junction); },
                             "(k, 6) visible junction segments (where bodies interpenetrate).")
      .def_property_readonly("outline", [](const PyHiddenLines& h) { return segments_of(h.result.visible, LineKind::Outline); },
                             "(k, 6) visible outline segments (contours of smooth parts).")
      .def_property_readonly("smooth", [](const PyHiddenLines& h) { return segments_of(h.result.visible, LineKind::Smooth); },
                             "(k, 6) visible smooth-edge segments (with smooth=True).")
      .def_readonly("ms", &PyHiddenLines::ms)
      .def_property_readonly("stats", [](const PyHiddenLines& h) {
        const HlrStats& s = h.result.stats;
        py::dict d;
        d["bodies"] = s.bodies;
        d["pieces"] = s.pieces;
        d["edges"] = s.edges;
        d["back_edges"] = s.back_edges;
        d["occlusion_tests"] = s.occlusion_tests;
        d["junction_segments"] = s.junction_segments;
        d["smooth_edges"] = s.smooth_edges;
        d["outline_segments"] = s.outline_segments;
        return d;
      })
      .def("to_json", [](const PyHiddenLines& h) { return io::hidden_lines_json(h.result, h.ms); },
           "The JSON of `hedra hlr --json` (one line).")
      .def("svg", &svg_of, py::arg("hidden") = py::none(), py::arg("title") = "",
           py::arg("fit") = false,
           "The drawing as SVG text (hidden lines dashed when computed, or as asked), framed as "
           "render() frames the scene (fit=True: fitted to the image).")
      .def("_repr_svg_", [](const PyHiddenLines& h) { return svg_of(h, std::nullopt, "", false); });
  m.def("hidden_lines",
        [](const PyScene& s, bool hidden, bool junctions, double crease_angle, bool smooth,
           py::object progress) {
          PyHiddenLines out;
          out.width = s.scene.camera.width;
          out.height = s.scene.camera.height;
          out.background = s.scene.image.background;
          out.hidden = hidden;
          const Scene scene = s.scene;
          out.view = scene_view(scene, out.width, out.height);
          HlrOptions options;
          options.hidden = hidden;
          options.junctions = junctions;
          options.crease_angle = crease_angle;
          options.smooth = smooth;
          PyProgress reporter{progress, {}};
          options.progress = reporter.callback();
          const auto t0 = Clock::now();
          try {
            py::gil_scoped_release release;
            out.result = hidden_lines(scene, options);
          } catch (const InvalidInput& e) {
            rethrow_with_source(s, e);
          } catch (const Cancelled&) {
            reporter.rethrow();
          }
          out.ms = ms_since(t0);
          return out;
        },
        py::arg("scene"), py::arg("hidden") = true, py::arg("junctions") = true,
        py::arg("crease_angle") = 30.0, py::arg("smooth") = false, py::arg("progress") = py::none(),
        "Exact hidden-line removal with the scene's camera: sharp edges (turning by more than "
        "crease_angle degrees), outlines of smooth parts, smooth edges when smooth=True. "
        "progress(done) returning False cancels (hedra.Cancelled).");

  // ---- shadows ----
  py::class_<PyShadows>(m, "Shadows", "Exact shadows of every light on every face.")
      .def_readonly("ms", &PyShadows::ms)
      .def_property_readonly("light_count", [](const PyShadows& s) { return s.result.lights.size(); })
      .def("faces",
           [](const PyShadows& s, int light) {
             if (light < 0 || light >= static_cast<int>(s.result.lights.size()))
               throw InvalidInput("light " + std::to_string(light) + " out of range");
             py::list out;
             for (const FaceShadow& fs : s.result.lights[static_cast<size_t>(light)].faces)
               out.append(face_record(s, fs));
             return out;
           },
           py::arg("light") = 0,
           "Per face of every visible body: body, face, area, self_shadowed, grazing, visible, "
           "shadow_area, lit_fraction, polygons [(outer (k, 3), [holes])].")
      .def("face",
           [](const PyShadows& s, const std::string& body, int face, int light) {
             const int b = body_index(s.scene, body);
             if (s.result.first_face[static_cast<size_t>(b)] < 0) throw InvalidInput("body '" + body + "' is hidden");
             if (face < 0 || face >= s.scene.bodies()[static_cast<size_t>(b)].body.face_count())
               throw InvalidInput("body '" + body + "' has no face " + std::to_string(face));
             if (light < 0 || light >= static_cast<int>(s.result.lights.size()))
               throw InvalidInput("light " + std::to_string(light) + " out of range");
             return face_record(s, s.result.face(light, b, face));
           },
           py::arg("body"), py::arg("face"), py::arg("light") = 0)
      .def_property_readonly("counts", [](const PyShadows& s) {
        py::list out;
        for (const ShadowCount& c : s.result.counts) {
          py::dict d;
          d["body"] = s.scene.bodies()[static_cast<size_t>(c.body)].name;
          d["face"] = c.face;
          d["count"] = c.count;
          d["area"] = c.area;
          d["polygons"] = polygons_of(c.polygons);
          out.append(d);
        }
        return out;
      })
      .def("to_json", [](const PyShadows& s) {
        return io::shadows_json(s.scene, s.source, s.result, s.visible_parts, s.ms);
      }, "The JSON of `hedra shadows --json` (one line; 'scene' is the file read).");
  m.def("shadows",
        [](const PyScene& s, bool visible, int threads, py::object progress) {
          if (s.scene.lights.empty())
            throw InvalidInput((s.source.empty() ? std::string() : s.source + ": ") +
                               "the scene has no lights (shadows need at least one)");
          PyShadows out{s.scene, s.source, {}, visible, 0};
          ShadowOptions options;
          options.visible_parts = visible;
          options.threads = threads;
          PyProgress reporter{progress, {}};
          options.progress = reporter.callback();
          const auto t0 = Clock::now();
          try {
            py::gil_scoped_release release;
            out.result = compute_shadows(out.scene, options);
          } catch (const InvalidInput& e) {
            rethrow_with_source(s, e);
          } catch (const Cancelled&) {
            reporter.rethrow();
          }
          out.ms = ms_since(t0);
          return out;
        },
        py::arg("scene"), py::arg("visible") = false, py::arg("threads") = 0,
        py::arg("progress") = py::none(),
        "Self shadows and exact cast-shadow polygons of every light on every face "
        "(visible=True: also the parts the camera sees).");

  // ---- sun studies ----
  py::class_<PySunStudy>(m, "SunStudy", "Lit fractions per time step and hours of direct sun per face.")
      .def_property_readonly("times", [](const PySunStudy& s) {
        py::list out;
        for (const SunStep& st : s.study.steps) out.append(st.time.to_string());
        return out;
      })
      .def_property_readonly("elevation_deg", [](const PySunStudy& s) {
        std::vector<double> v;
        for (const SunStep& st : s.study.steps) v.push_back(st.elevation_deg);
        return doubles_array(v);
      })
      .def_property_readonly("azimuth_deg", [](const PySunStudy& s) {
        std::vector<double> v;
        for (const SunStep& st : s.study.steps) v.push_back(st.azimuth_deg);
        return doubles_array(v);
      })
      .def_property_readonly("sun_up", [](const PySunStudy& s) {
        std::vector<bool> v;
        for (const SunStep& st : s.study.steps) v.push_back(st.sun_up);
        return v;
      })
      .def_property_readonly("faces", [](const PySunStudy& s) {
        py::list out;
        for (size_t b = 0; b < s.scene.bodies().size(); ++b) {
          if (s.study.first_face[b] < 0) continue;
          for (int f = 0; f < s.scene.bodies()[b].body.face_count(); ++f)
            out.append(py::make_tuple(s.scene.bodies()[b].name, f));
        }
        return out;
      }, "(body, face) of each column of lit_fraction and entry of sun_hours.")
      .def_property_readonly("lit_fraction", [](const PySunStudy& s) {
        const size_t faces = s.study.sun_hours.size();
        std::vector<double> flat;
        for (const SunStep& st : s.study.steps) flat.insert(flat.end(), st.lit_fraction.begin(), st.lit_fraction.end());
        return rows_array(flat, faces);
      }, "(steps, faces) lit fraction of each face at each step.")
      .def_property_readonly("sun_hours", [](const PySunStudy& s) { return doubles_array(s.study.sun_hours); })
      .def("hours", [](const PySunStudy& s, const std::string& body, int face) {
        const int b = body_index(s.scene, body);
        const int first = s.study.first_face[static_cast<size_t>(b)];
        if (first < 0 || face < 0 || face >= s.scene.bodies()[static_cast<size_t>(b)].body.face_count())
          throw InvalidInput("no face " + std::to_string(face) + " of a visible body '" + body + "'");
        return s.study.sun_hours[static_cast<size_t>(first + face)];
      }, py::arg("body"), py::arg("face"))
      .def_property_readonly("grid_points", [](const PySunStudy& s) { return points_array(s.study.grid_points); })
      .def_property_readonly("grid_hours", [](const PySunStudy& s) { return doubles_array(s.study.grid_hours); })
      .def_property_readonly("latitude", [](const PySunStudy& s) { return s.options.latitude; })
      .def_property_readonly("longitude", [](const PySunStudy& s) { return s.options.longitude; })
      .def_property_readonly("step_minutes", [](const PySunStudy& s) { return s.options.step_minutes; })
      .def_property_readonly("first_step", [](const PySunStudy& s) { return s.study.first_step; },
                             "Index of the first step in the whole schedule (slices).")
      .def_static("combine", &combine_studies, py::arg("parts"), "As hedra.combine_sun_studies.")
      .def("to_json", [](const PySunStudy& s) { return io::sun_study_json(s.scene, s.options, s.study); },
           "The 'sun_study' object of `hedra shadows --json --sun-hours` (one line).")
      .def(py::pickle(
          [](const PySunStudy& s) {
            // Every double as its bytes, so a study sent to another process comes back exact.
            const SunStudyOptions& o = s.options;
            py::list steps;
            for (const SunStep& st : s.study.steps)
              steps.append(py::make_tuple(time_state(st.time), st.elevation_deg, st.azimuth_deg, st.sun_up,
                                          doubles_bytes(st.lit_fraction.data(), st.lit_fraction.size()),
                                          py::bytes(st.grid_lit.data(), st.grid_lit.size())));
            std::vector<double> grid;
            for (const Vec3& p : s.study.grid_points) grid.insert(grid.end(), {p.x(), p.y(), p.z()});
            return py::make_tuple(
                1, scene_state(PyScene{s.scene, ""}),
                py::make_tuple(o.latitude, o.longitude, time_state(o.start), time_state(o.end), o.step_minutes,
                               o.grid_body, o.grid_face, o.grid_spacing, o.threads, o.first_step,
                               o.step_count, s.study.first_step),
                steps, doubles_bytes(s.study.sun_hours.data(), s.study.sun_hours.size()),
                py::cast(s.study.first_face), doubles_bytes(grid.data(), grid.size()),
                doubles_bytes(s.study.grid_hours.data(), s.study.grid_hours.size()));
          },
          [](const py::tuple& t) {
            if (t.size() != 8 || t[0].cast<int>() != 1) throw InvalidInput("SunStudy: unknown pickle state");
            PySunStudy s;
            s.scene = scene_from(t[1].cast<py::tuple>()).scene;
            const py::tuple o = t[2].cast<py::tuple>();
            s.options.latitude = o[0].cast<double>();
            s.options.longitude = o[1].cast<double>();
            s.options.start = time_from(o[2]);
            s.options.end = time_from(o[3]);
            s.options.step_minutes = o[4].cast<double>();
            s.options.grid_body = o[5].cast<std::string>();
            s.options.grid_face = o[6].cast<int>();
            s.options.grid_spacing = o[7].cast<double>();
            s.options.threads = o[8].cast<int>();
            s.options.first_step = o[9].cast<int>();
            s.options.step_count = o[10].cast<int>();
            s.study.first_step = o[11].cast<int>();
            for (const py::handle h : t[3].cast<py::list>()) {
              const py::tuple st = h.cast<py::tuple>();
              SunStep step;
              step.time = time_from(st[0]);
              step.elevation_deg = st[1].cast<double>();
              step.azimuth_deg = st[2].cast<double>();
              step.sun_up = st[3].cast<bool>();
              step.lit_fraction = doubles_from(st[4]);
              const std::string lit = st[5].cast<std::string>();
              step.grid_lit.assign(lit.begin(), lit.end());
              s.study.steps.push_back(std::move(step));
            }
            s.study.sun_hours = doubles_from(t[4]);
            s.study.first_face = t[5].cast<std::vector<int>>();
            const std::vector<double> grid = doubles_from(t[6]);
            for (size_t i = 0; i + 2 < grid.size(); i += 3) s.study.grid_points.emplace_back(grid[i], grid[i + 1], grid[i + 2]);
            s.study.grid_hours = doubles_from(t[7]);
            return s;
          }));
  m.def("sun_study", &run_sun_study, py::arg("scene"), py::arg("start"), py::arg("end"),
        py::arg("step_minutes") = 60.0, py::arg("latitude") = py::none(),
        py::arg("longitude") = py::none(), py::arg("grid") = py::none(), py::arg("threads") = 0,
        py::arg("grid_body") = "", py::arg("grid_face") = -1, py::arg("grid_spacing") = 0.0,
        py::arg("first_step") = 0, py::arg("step_count") = -1,
        "Shadows from start to end (ISO 8601 UTC, or hh:mm on the date of the scene's sun) every "
        "step_minutes; place from the scene's sun unless given. grid=(body, face, spacing). "
        "first_step, step_count: only that slice of the schedule (-1: to the end), to be joined "
        "by combine_sun_studies.");
  m.def("combine_sun_studies", &combine_studies, py::arg("parts"),
        "The whole study from slices computed apart (in schedule order, covering it exactly): "
        "equal to the single sun_study bit for bit.");
  m.def("sun_study_steps",
        [](const PyScene& s, const std::string& start, const std::string& end, double step_minutes) {
          const Light* sun = scene_sun(s.scene);
          SunStudyOptions o;
          o.start = time_of(start, sun ? &sun->time : nullptr);
          o.end = time_of(end, sun ? &sun->time : nullptr);
          o.step_minutes = step_minutes;
          return sun_study_steps(o);
        },
        py::arg("scene"), py::arg("start"), py::arg("end"), py::arg("step_minutes") = 60.0,
        "Number of steps of the whole schedule start, start + step, ..., end.");

  // ---- rendering ----
  m.def("render",
        [](const PyScene& s, int width, int height, const std::string& shadows, const std::string& shading,
           int aa, bool lines, double ambient, const std::string& attenuation, int threads,
           py::object progress) {
          RenderOptions options;
          options.width = width;
          options.height = height;
          options.shadows = ShadowSettings::parse(shadows);
          options.shading = shading_of(shading);
          options.aa = aa;
          options.ambient = ambient;
          options.attenuation = Attenuation::parse(attenuation);
          options.threads = threads;
          PyProgress reporter{progress, {}};
          options.progress = reporter.callback();
          const Scene scene = s.scene;
          Image image;
          try {
            py::gil_scoped_release release;
            image = render(scene, options);
            if (lines) draw_hidden_lines(image, scene);
          } catch (const InvalidInput& e) {
            rethrow_with_source(s, e);
          } catch (const Cancelled&) {
            reporter.rethrow();
          }
          py::array_t<std::uint8_t> out({static_cast<py::ssize_t>(image.height), static_cast<py::ssize_t>(image.width),
                                         py::ssize_t{3}});
          std::memcpy(out.mutable_data(), image.rgb.data(), image.rgb.size());
          return out;
        },
        py::arg("scene"), py::arg("width") = 0, py::arg("height") = 0, py::arg("shadows") = "exact",
        py::arg("shading") = "phong", py::arg("aa") = 1, py::arg("lines") = false, py::arg("ambient") = 1.0,
        py::arg("attenuation") = "none", py::arg("threads") = 0, py::arg("progress") = py::none(),
        "Shaded image, (h, w, 3) uint8 (0 sizes: the scene camera's). progress(done) returning "
        "False cancels (hedra.Cancelled).");
}

}  // namespace hedra::python
