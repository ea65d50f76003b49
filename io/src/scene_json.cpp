#include "hedra/io/scene_json.h"

#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <optional>

#include <nlohmann/json.hpp>

#include "hedra/io/atomic_file.h"
#include "json_value.h"
#include "hedra/io/mesh_io.h"
#include "hedra/io/text_reader.h"
#include "hedra/mesh/boolean.h"
#include "hedra/mesh/open_surface.h"
#include "hedra/mesh/self_intersection.h"
#include "hedra/core/error.h"
#include "hedra/core/face_geometry.h"
#include "hedra/core/triangulate.h"
#include "hedra/scene/lod.h"
#include "hedra/core/primitives.h"

namespace hedra::io {
namespace {

namespace fs = std::filesystem;
using Kind = JsonValue::Kind;

std::string join(std::initializer_list<const char*> words) {
  std::string s;
  for (const char* w : words) s += (s.empty() ? "" : ", ") + std::string(w);
  return s;
}

class SceneReader {
 public:
  SceneReader(std::string path, double tolerance) : path_(std::move(path)) {
    mesh_options_.merge.coplanar_tolerance = tolerance;
  }

  Scene read(const JsonValue& root) {
    if (root.kind != Kind::Object) fail(root, "a scene file holds a JSON object");
    allow(root, {"version", "tolerance", "bodies", "camera", "lights", "image"});
    if (const JsonValue* v = root.find("version"))
      if (integer(*v, "'version'") != 1) fail(*v, "unsupported version (this reader knows 1)");
    // Mesh import tolerance (MergeOptions::coplanar_tolerance); the command's --tolerance wins.
    if (const JsonValue* t = root.find("tolerance"))
      if (!(mesh_options_.merge.coplanar_tolerance > 0))
        mesh_options_.merge.coplanar_tolerance = positive(*t, "'tolerance'");
    Scene scene;
    if (const JsonValue* image = root.find("image")) read_image(*image, scene);
    if (const JsonValue* camera = root.find("camera")) read_camera(*camera, scene);
    try {
      scene.camera.validate();
    } catch (const InvalidInput& e) {
      fail(root.find("camera") ? *root.find("camera") : root, e.what());
    }
    if (const JsonValue* lights = root.find("lights")) {
      if (lights->kind != Kind::Array) fail(*lights, "'lights' must be an array");
      for (const JsonValue& l : lights->items) scene.lights.push_back(read_light(l));
    }
    const JsonValue& bodies = member(root, "bodies");
    if (bodies.kind != Kind::Array) fail(bodies, "'bodies' must be an array");
    if (bodies.items.empty()) fail(bodies, "'bodies' is empty");
    camera_ = &scene.camera;
    view_height_ = std::nullopt;
    bodies_json_ = &bodies;
    for (const JsonValue& b : bodies.items) read_body(b, scene);
    context_.clear();
    return scene;
  }

 private:
  // ---- errors and typed access -------------------------------------------------------------
  [[noreturn]] void fail(const JsonValue& at, const std::string& message) const {
    throw InvalidInput(where(at) + context_ + message);
  }

  void allow(const JsonValue& object, std::initializer_list<const char*> keys) const {
    for (size_t i = 0; i < object.members.size(); ++i) {
      const std::string& key = object.members[i].first;
      bool known = false;
      for (const char* k : keys) known = known || key == k;
      if (!known) {
        JsonValue at;
        at.line = object.key_positions[i].first;
        at.column = object.key_positions[i].second;
        fail(at, "unknown key '" + key + "' (expected one of: " + join(keys) + ")");
      }
    }
  }

  const JsonValue& member(const JsonValue& object, const char* key) const {
    if (object.kind != Kind::Object) fail(object, "expected an object");
    const JsonValue* v = object.find(key);
    if (!v) fail(object, std::string("missing '") + key + "'");
    return *v;
  }

  double number(const JsonValue& v, const std::string& what) const {
    if (v.kind != Kind::Number) fail(v, what + " must be a number, not " + v.kind_name());
    return v.number;
  }
  double positive(const JsonValue& v, const std::string& what) const {
    double x = number(v, what);
    if (!(x > 0)) fail(v, what + " must be positive");
    return x;
  }
  int integer(const JsonValue& v, const std::string& what) const {
    double x = number(v, what);
    if (x != std::floor(x) || std::abs(x) > 1e9) fail(v, what + " must be an integer");
    return static_cast<int>(x);
  }
  std::string text(const JsonValue& v, const std::string& what) const {
    if (v.kind != Kind::String) fail(v, what + " must be a string, not " + v.kind_name());
    return v.string;
  }
  bool flag(const JsonValue& v, const std::string& what) const {
    if (v.kind != Kind::Bool) fail(v, what + " must be true or false");
    return v.boolean;
  }
  std::vector<double> numbers(const JsonValue& v, size_t n, const std::string& what) const {
    if (v.kind != Kind::Array || v.items.size() != n)
      fail(v, what + " must be an array of " + std::to_string(n) + " numbers");
    std::vector<double> out;
    for (const JsonValue& x : v.items) out.push_back(number(x, what));
    return out;
  }
  Vec3 vec3(const JsonValue& v, const std::string& what) const {
    auto x = numbers(v, 3, what);
    return {x[0], x[1], x[2]};
  }
  Vec2 vec2(const JsonValue& v, const std::string& what) const {
    auto x = numbers(v, 2, what);
    return {x[0], x[1]};
  }
  Polygon2 polygon(const JsonValue& v, const std::string& what) const {
    if (v.kind != Kind::Array) fail(v, what + " must be an array of [x, y] points");
    if (v.items.size() < 3) fail(v, what + " needs at least 3 points");
    Polygon2 p;
    for (const JsonValue& q : v.items) p.push_back(vec2(q, what + " point"));
    return p;
  }
  std::pair<double, double> range(const JsonValue& v, const std::string& what) const {
    auto x = numbers(v, 2, what);
    return {x[0], x[1]};
  }

  // ---- image, camera, lights, material -----------------------------------------------------
  void read_image(const JsonValue& v, Scene& scene) const {
    allow(v, {"width", "height", "background"});
    if (const JsonValue* w = v.find("width")) scene.camera.width = integer(*w, "'width'");
    if (const JsonValue* h = v.find("height")) scene.camera.height = integer(*h, "'height'");
    if (const JsonValue* b = v.find("background")) scene.image.background = vec3(*b, "'background'");
  }

  void read_camera(const JsonValue& v, Scene& scene) const {
    if (v.kind != Kind::Object) fail(v, "'camera' must be an object");
    Camera& c = scene.camera;
    const std::string projection = text(member(v, "projection"), "'projection'");
    if (projection == "parallel") {
      allow(v, {"projection", "direction", "up"});
      c.projection = Camera::Projection::Parallel;
      c.direction = vec3(member(v, "direction"), "'direction'");
      c.up = v.find("up") ? vec3(*v.find("up"), "'up'") : Vec3(0, 1, 0);
    } else if (projection == "perspective") {
      allow(v, {"projection", "eye", "target", "up", "fov_deg"});
      c.projection = Camera::Projection::Perspective;
      c.eye = vec3(member(v, "eye"), "'eye'");
      c.target = vec3(member(v, "target"), "'target'");
      c.up = v.find("up") ? vec3(*v.find("up"), "'up'") : Vec3(0, 0, 1);
      c.fov_deg = v.find("fov_deg") ? number(*v.find("fov_deg"), "'fov_deg'") : 45;
    } else {
      fail(member(v, "projection"), "'projection' must be \"parallel\" or \"perspective\"");
    }
  }

  Light read_light(const JsonValue& v) const {
    if (v.kind != Kind::Object) fail(v, "a light must be an object");
    const std::string type = text(member(v, "type"), "light 'type'");
    Light l;
    auto common = [&] {
      if (const JsonValue* i = v.find("intensity")) l.intensity = number(*i, "'intensity'");
      if (const JsonValue* c = v.find("color")) l.color = vec3(*c, "'color'");
    };
    try {
      if (type == "directional") {
        allow(v, {"type", "direction", "intensity", "color"});
        l.type = Light::Type::Directional;
        l.direction = vec3(member(v, "direction"), "'direction'");
      } else if (type == "point") {
        allow(v, {"type", "position", "intensity", "color"});
        l.type = Light::Type::Point;
        l.position = vec3(member(v, "position"), "'position'");
      } else if (type == "spot") {
        allow(v, {"type", "position", "direction", "cone_deg", "falloff", "intensity", "color"});
        l.type = Light::Type::Spot;
        l.position = vec3(member(v, "position"), "'position'");
        l.direction = vec3(member(v, "direction"), "'direction'");
        l.cone_deg = number(member(v, "cone_deg"), "'cone_deg'");
        if (const JsonValue* f = v.find("falloff")) l.falloff = number(*f, "'falloff'");
      } else if (type == "sun") {
        allow(v, {"type", "latitude", "longitude", "time", "intensity", "color"});
        const double lat = number(member(v, "latitude"), "'latitude'");
        const double lon = number(member(v, "longitude"), "'longitude'");
        const UtcTime t = UtcTime::parse(text(member(v, "time"), "'time'"));
        l = Light::sun(lat, lon, t);
      } else {
        fail(member(v, "type"), "light 'type' must be directional, point, spot or sun");
      }
      common();
      l.validate();
    } catch (const InvalidInput& e) {
      if (std::string(e.what()).rfind(path_, 0) == 0) throw;
      fail(v, e.what());
    }
    return l;
  }

  Material read_material(const JsonValue& v) const {
    allow(v, {"color", "ka", "kd", "ks", "shininess"});
    Material m;
    if (const JsonValue* c = v.find("color")) m.color = vec3(*c, "'color'");
    if (const JsonValue* x = v.find("ka")) m.ka = number(*x, "'ka'");
    if (const JsonValue* x = v.find("kd")) m.kd = number(*x, "'kd'");
    if (const JsonValue* x = v.find("ks")) m.ks = number(*x, "'ks'");
    if (const JsonValue* x = v.find("shininess")) m.shininess = number(*x, "'shininess'");
    try {
      m.validate();
    } catch (const InvalidInput& e) {
      fail(v, e.what());
    }
    return m;
  }

  Transform read_transform(const JsonValue& v) const {
    if (v.kind != Kind::Array) fail(v, "'transform' must be an array of steps");
    Transform t;
    for (const JsonValue& step : v.items) {
      if (step.kind != Kind::Object || step.members.size() != 1)
        fail(step, "a transform step is an object with one key: translate, rotate, scale or matrix");
      const auto& [key, arg] = step.members[0];
      if (key == "translate") {
        t = t * Transform::translation(vec3(arg, "'translate'"));
      } else if (key == "rotate") {
        allow(arg, {"axis", "deg", "about"});
        Vec3 about = arg.find("about") ? vec3(*arg.find("about"), "'about'") : Vec3::Zero();
        Vec3 axis = vec3(member(arg, "axis"), "'axis'");
        if (axis.norm() == 0) fail(member(arg, "axis"), "'axis' must not be zero");
        t = t * Transform::rotation(axis, number(member(arg, "deg"), "'deg'"), about);
      } else if (key == "scale") {
        allow(arg, {"factors", "about"});
        Vec3 about = arg.find("about") ? vec3(*arg.find("about"), "'about'") : Vec3::Zero();
        const JsonValue& f = member(arg, "factors");
        Vec3 k = f.kind == Kind::Number ? Vec3::Constant(f.number) : vec3(f, "'factors'");
        if ((k.array() == 0).any()) fail(f, "scale factors must not be zero");
        t = t * Transform::scaling(k, about);
      } else if (key == "matrix") {
        if (arg.kind != Kind::Array || arg.items.size() != 4)
          fail(arg, "'matrix' must be 4 rows of 4 numbers (row vectors, as in the course)");
        Mat4 m;
        for (int r = 0; r < 4; ++r) {
          auto row = numbers(arg.items[r], 4, "'matrix' row");
          for (int c = 0; c < 4; ++c) m(r, c) = row[c];
        }
        if (std::abs(m.determinant()) == 0) fail(arg, "'matrix' is singular");
        t = t * Transform(m);
      } else {
        fail(step, "unknown transform step '" + key + "' (expected translate, rotate, scale or matrix)");
      }
    }
    return t;
  }

  // ---- bodies ------------------------------------------------------------------------------
  static constexpr std::initializer_list<const char*> kShapes = {
      "box", "prism", "pyramid", "frustum", "regular_prism", "cylinder", "cone", "sphere",
      "mesh", "polyhedron", "unite", "subtract", "intersect"};

  const JsonValue* shape_of(const JsonValue& b, std::string& shape) const {
    const JsonValue* found = nullptr;
    for (const char* s : kShapes)
      if (const JsonValue* v = b.find(s)) {
        if (found) fail(*v, "a body has exactly one shape, found '" + shape + "' and '" + s + "'");
        found = v;
        shape = s;
      }
    if (!found)
      fail(b, "missing shape (one of: box, prism, pyramid, frustum, regular_prism, cylinder, cone, "
              "sphere, mesh, polyhedron, unite, subtract, intersect)");
    return found;
  }

  // Chordal tolerance from "tolerance" or "pixel_tolerance" for a curved primitive whose local
  // bounding sphere is (centre, radius), placed by `t`.
  double curved_tolerance(const JsonValue& v, const Vec3& centre, double radius, const Transform& t,
                          std::string& note) {
    const JsonValue* tol = v.find("tolerance");
    const JsonValue* px = v.find("pixel_tolerance");
    if (tol && px) fail(v, "give either 'tolerance' or 'pixel_tolerance', not both");
    if (tol) {
      double x = positive(*tol, "'tolerance'");
      note = "chordal tolerance " + format_number(x) + " (given)";
      return x;
    }
    if (!px) fail(v, "missing 'tolerance' or 'pixel_tolerance'");
    const double pixels = positive(*px, "'pixel_tolerance'");
    // The chordal error scales with the transform's largest stretch.
    const double stretch = t.matrix().topLeftCorner<3, 3>().jacobiSvd().singularValues()(0);
    const Vec3 world_centre = t.apply(centre);
    const double world_radius = radius * stretch;
    if (camera_->projection == Camera::Projection::Parallel && !view_height_)
      view_height_ = parallel_view_height(*camera_, scene_extent());
    try {
      double world = chordal_tolerance_for_pixels(pixels, world_centre, world_radius, *camera_,
                                                  view_height_.value_or(0), &note);
      return world / stretch;
    } catch (const InvalidInput& e) {
      fail(*px, e.what());
    }
  }

  static std::string format_number(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", x);
    return buf;
  }

  // Analytic bounding box of every visible body (before tessellation), for fitting a parallel
  // view: pixel tolerances then do not depend on the order of bodies in the file.
  Eigen::AlignedBox3d scene_extent() {
    std::map<std::string, Eigen::AlignedBox3d> boxes;
    Eigen::AlignedBox3d all;
    all.setEmpty();
    const std::string saved = context_;
    for (const JsonValue& b : bodies_json_->items) {
      if (b.kind != Kind::Object) continue;
      const JsonValue* n = b.find("name");
      if (!n || n->kind != Kind::String) continue;
      context_ = "body '" + n->string + "': ";
      std::string shape;
      const JsonValue& s = *shape_of(b, shape);
      Eigen::AlignedBox3d box;
      box.setEmpty();
      auto take = [&](const std::string& name) {
        auto it = boxes.find(name);
        return it == boxes.end() ? Eigen::AlignedBox3d() : it->second;
      };
      if (shape == "box") {
        box.extend(vec3(member(s, "min"), "'min'"));
        box.extend(vec3(member(s, "max"), "'max'"));
      } else if (shape == "prism" || shape == "pyramid" || shape == "frustum") {
        const JsonValue& outline = member(s, shape == "prism" ? "polygon" : "base");
        for (const Vec2& p : polygon(outline, "outline")) {
          if (shape == "prism") {
            auto [z0, z1] = range(member(s, "z"), "'z'");
            box.extend(Vec3(p.x(), p.y(), z0));
            box.extend(Vec3(p.x(), p.y(), z1));
          } else {
            const JsonValue& z = member(s, "z");
            box.extend(Vec3(p.x(), p.y(), z.kind == Kind::Number ? z.number : range(z, "'z'").first));
          }
        }
        if (shape != "prism") box.extend(vec3(member(s, "apex"), "'apex'"));
      } else if (shape == "regular_prism" || shape == "cylinder" || shape == "cone") {
        const double r = positive(member(s, "radius"), "'radius'");
        auto [z0, z1] = range(member(s, "z"), "'z'");
        box.extend(Vec3(-r, -r, z0));
        box.extend(Vec3(r, r, z1));
      } else if (shape == "sphere") {
        const Vec3 c = vec3(member(s, "center"), "'center'");
        const double r = positive(member(s, "radius"), "'radius'");
        box.extend(c - Vec3::Constant(r));
        box.extend(c + Vec3::Constant(r));
      } else if (shape == "polyhedron") {
        for (const JsonValue& p : member(s, "vertices").items) box.extend(vec3(p, "vertex"));
      } else if (shape == "mesh") {
        if (const std::optional<PolygonSoup> open = open_mesh(s)) {
          for (const auto& poly : open->polygons)
            for (int w : poly) box.extend(open->vertices[static_cast<size_t>(w)]);
        } else {
          for (const Body& m : read_mesh(s)) box.extend(m.bbox());
        }
      } else if (s.kind == Kind::Array && s.items.size() == 2 &&
                 s.items[0].kind == Kind::String && s.items[1].kind == Kind::String) {
        Eigen::AlignedBox3d a = take(s.items[0].string), c = take(s.items[1].string);
        if (shape == "unite") box = a.merged(c);
        else if (shape == "subtract") box = a;
        else box = a.intersection(c);
      }
      Eigen::AlignedBox3d placed;
      placed.setEmpty();
      if (!box.isEmpty()) {
        Transform t = b.find("transform") ? read_transform(*b.find("transform")) : Transform();
        for (int i = 0; i < 8; ++i)
          placed.extend(t.apply(Vec3(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)))));
      }
      boxes[n->string] = placed;
      const JsonValue* hidden = b.find("hidden");
      if (!(hidden && hidden->kind == Kind::Bool && hidden->boolean)) all.extend(placed);
    }
    context_ = saved;
    if (all.isEmpty()) all.extend(Vec3::Zero());
    return all;
  }

  std::string mesh_path(const JsonValue& v) const {
    fs::path p(text(v, "'mesh'"));
    if (p.is_relative()) p = fs::path(path_).parent_path() / p;
    return p.string();
  }

  // The bodies of a "mesh" file; a file that cannot be read is reported at the scene's line
  // and body too (the mesh's own errors already name the mesh file and its line).
  std::vector<Body> read_mesh(const JsonValue& v) const {
    const std::string path = mesh_path(v);
    try {
      return read_bodies(path, mesh_options_);
    } catch (const IoError& e) {
      throw IoError(path_ + ":" + std::to_string(v.line) + ":" + std::to_string(v.column) + ": " +
                    context_ + "'mesh': " + e.what());
    }
  }

  // The polygons of a "mesh" file that is an open surface (is_open_surface), else none. Read
  // at most once per body: the answer is kept by file path.
  std::optional<PolygonSoup> open_mesh(const JsonValue& v) {
    const std::string path = mesh_path(v);
    if (auto it = open_meshes_.find(path); it != open_meshes_.end()) return it->second;
    std::optional<PolygonSoup> out;
    try {
      PolygonSoup soup = read_soup(path);
      if (is_open_surface(soup)) out = std::move(soup);
    } catch (const Error&) {
      // Unreadable or malformed: not a surface; read_mesh reports it.
    }
    open_meshes_[path] = out;
    return out;
  }

  // The polygons of a "polyhedron" that is an open surface, else none (a face of fewer than 3
  // vertices is not one of a surface). A face with holes enters as its triangles
  // (triangulate_polygon in its Newell plane): their shared edges pair up inside the face, its
  // loops are the surface's edges there, and two_sided_faces merges exactly coplanar triangles
  // back into convex faces.
  std::optional<PolygonSoup> open_polyhedron(const JsonValue& s) const {
    const JsonValue* vs = s.find("vertices");
    const JsonValue* fs = s.find("faces");
    if (!vs || !fs || vs->kind != Kind::Array || fs->kind != Kind::Array) return std::nullopt;
    PolygonSoup soup;
    for (const JsonValue& p : vs->items) soup.vertices.push_back(vec3(p, "a vertex"));
    for (const JsonValue& f : fs->items) {
      const Face face = read_face(f);
      for (const auto& loop : face.loops) {
        if (loop.size() < 3) return std::nullopt;
        for (int v : loop)
          if (v < 0 || static_cast<size_t>(v) >= soup.vertices.size()) return std::nullopt;
      }
      if (face.loops.size() == 1) {
        soup.polygons.push_back(face.loops[0]);
        continue;
      }
      try {
        const Vec3 normal = newell_normal(soup.vertices, face.loops[0]);
        for (const auto& t : triangulate_polygon(soup.vertices, face.loops, normal))
          soup.polygons.push_back({t[0], t[1], t[2]});
      } catch (const InvalidInput&) {
        return std::nullopt;  // the solid's path names the face and why
      }
    }
    if (!is_open_surface(soup)) return std::nullopt;
    return soup;
  }

  // Adds an open surface (a "mesh" or "polyhedron" body that is not closed, `why` being the
  // error that says so) as one two-sided body of its faces (two_sided_surface), named as the
  // surface, and its record; `tolerance`: two_sided_surface's.
  void add_surface(const JsonValue& b, const std::string& name, const JsonValue& s,
                   PolygonSoup soup, const Transform& t, const std::string& why, double tolerance,
                   Scene& scene) {
    if (!t.matrix().isIdentity()) {
      // As Body::transformed: projective maps must keep w > 0; reflections reverse the loops.
      for (size_t i = 0; i < soup.vertices.size(); ++i) {
        const Vec4 h = t.apply_homogeneous(soup.vertices[i]);
        if (!(h.w() > 0)) fail(s, "vertex " + std::to_string(i) + " maps onto or behind the centre of projection");
        soup.vertices[i] = h.w() == 1.0 ? Vec3(h.head<3>()) : Vec3(h.head<3>() / h.w());
      }
      if (t.matrix().determinant() < 0)
        for (auto& poly : soup.polygons) std::reverse(poly.begin(), poly.end());
    }
    SceneSurface record = SceneSurface::of(name, soup);
    record.not_solid = (why.rfind(path_ + ":", 0) == 0 ? why : where(s) + context_ + why) +
                       " (an open surface: hlr, shadows and render take it as two-sided faces)";
    std::optional<Body> surface;
    try {
      surface = two_sided_surface(soup, tolerance);
    } catch (const InvalidInput& e) {
      fail(s, std::string("open surface: ") + e.what());
    }
    const Material material = b.find("material") ? read_material(*b.find("material")) : Material();
    const bool hidden = b.find("hidden") && flag(*b.find("hidden"), "'hidden'");
    SceneBody& added = scene.add(name, *surface, material);
    added.hidden = hidden;
    scene.surfaces.push_back(std::move(record));
  }

  // "file:line:column: " of a value.
  std::string where(const JsonValue& at) const {
    return path_ + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) + ": ";
  }


  // A primitive within the face budget; over it, the message adds how the tolerance was chosen
  // and how to allow more faces.
  template <class Build>
  auto within_budget(Build build, const std::string& note) const {
    try {
      return build();
    } catch (const FaceBudgetExceeded& e) {
      throw InvalidInput(std::string(e.what()) + pixel_note(note) +
                         "; a coarser tolerance needs fewer, or the shape's \"max_faces\" allows more");
    } catch (const InvalidInput& e) {
      throw InvalidInput(std::string(e.what()) + pixel_note(note));
    }
  }
  // The shape's face budget: its "max_faces", else kDefaultMaxFaces.
  int max_faces(const JsonValue& shape) const {
    const JsonValue* v = shape.find("max_faces");
    if (!v) return kDefaultMaxFaces;
    const int n = integer(*v, "'max_faces'");
    if (n < 8) fail(*v, "'max_faces' must be at least 8");
    return n;
  }

  // How a pixel tolerance became the chordal one, for messages about the latter.
  static std::string pixel_note(const std::string& note) {
    return note.find("pixel") == std::string::npos ? "" : " [" + note + "]";
  }

  const Body& operand(const JsonValue& v, const Scene& scene) const {
    const std::string name = text(v, "operand");
    for (const SceneSurface& surface : scene.surfaces)
      if (surface.name == name)
        fail(v, "operand '" + name + "' is an open surface; Booleans need closed bodies");
    if (!scene.contains(name))
      fail(v, "operand '" + name + "' is not a body defined earlier in the list");
    return scene.get(name).body;
  }

  void read_body(const JsonValue& b, Scene& scene) {
    context_.clear();
    if (b.kind != Kind::Object) fail(b, "a body must be an object");
    const std::string name = text(member(b, "name"), "'name'");
    if (name.empty()) fail(member(b, "name"), "'name' must not be empty");
    if (scene.contains(name)) fail(member(b, "name"), "body name '" + name + "' is used twice");
    context_ = "body '" + name + "': ";
    std::string shape;
    const JsonValue& s = *shape_of(b, shape);
    {
      std::vector<const char*> keys = {"name", "transform", "material", "hidden"};
      keys.push_back(shape.c_str());
      for (size_t i = 0; i < b.members.size(); ++i) {
        bool known = false;
        for (const char* k : keys) known = known || b.members[i].first == k;
        if (!known) {
          JsonValue at;
          at.line = b.key_positions[i].first;
          at.column = b.key_positions[i].second;
          fail(at, "unknown key '" + b.members[i].first +
                       "' (expected name, one shape, transform, material, hidden)");
        }
      }
    }
    const Transform t = b.find("transform") ? read_transform(*b.find("transform")) : Transform();
    std::string note;
    std::optional<Body> body;
    SmoothSurface surface;
    try {
      body = build(shape, s, t, scene, note, surface);
      if (!t.matrix().isIdentity()) body = body->transformed(t);
      // Validation up front (docs/io.md): bodies given by their vertices are checked for
      // self-intersection; a "mesh" file was checked when read, and again when a transform
      // rounded its vertices. Primitives and Booleans are valid by construction.
      if (shape == "polyhedron" || (shape == "mesh" && !t.matrix().isIdentity()))
        check_no_self_intersection(*body);
      surface = surface.transformed(t);
    } catch (const InvalidInput& e) {
      // A "mesh" or "polyhedron" that is an open surface (a scan, a terrain) is not a body, but
      // hidden lines, shadows and rendering take it as two-sided faces.
      std::optional<PolygonSoup> open;
      if (shape == "mesh") open = open_mesh(s);
      if (shape == "polyhedron") open = open_polyhedron(s);
      if (open) {
        // The import tolerance applies to meshes, as for closed ones.
        add_surface(b, name, s, std::move(*open), t, e.what(),
                    shape == "mesh" ? mesh_options_.merge.coplanar_tolerance : 0, scene);
        return;
      }
      if (std::string(e.what()).rfind(path_ + ":", 0) == 0) throw;
      fail(s, e.what());
    }
    SceneBody& added = scene.add(name, *body);
    if (const JsonValue* m = b.find("material")) added.material = read_material(*m);
    if (const JsonValue* h = b.find("hidden")) added.hidden = flag(*h, "'hidden'");
    added.lod_note = note;
    added.surface = surface;
  }

  // `surface` receives the analytic surface of a curved primitive (in its own frame).
  Body build(const std::string& shape, const JsonValue& s, const Transform& t, const Scene& scene,
             std::string& note, SmoothSurface& surface) {
    if (shape == "box") {
      allow(s, {"min", "max"});
      return box(vec3(member(s, "min"), "'min'"), vec3(member(s, "max"), "'max'"));
    }
    if (shape == "prism") {
      allow(s, {"polygon", "holes", "z"});
      std::vector<Polygon2> holes;
      if (const JsonValue* h = s.find("holes")) {
        if (h->kind != Kind::Array) fail(*h, "'holes' must be an array of polygons");
        for (const JsonValue& hole : h->items) holes.push_back(polygon(hole, "a hole"));
      }
      auto [z0, z1] = range(member(s, "z"), "'z'");
      return prism(polygon(member(s, "polygon"), "'polygon'"), z0, z1, holes);
    }
    if (shape == "pyramid") {
      allow(s, {"base", "z", "apex"});
      return pyramid(polygon(member(s, "base"), "'base'"), number(member(s, "z"), "'z'"),
                     vec3(member(s, "apex"), "'apex'"));
    }
    if (shape == "frustum") {
      allow(s, {"base", "z", "apex"});
      auto [z0, z1] = range(member(s, "z"), "'z'");
      return frustum(polygon(member(s, "base"), "'base'"), z0, vec3(member(s, "apex"), "'apex'"), z1);
    }
    if (shape == "regular_prism") {
      allow(s, {"sides", "radius", "z", "max_faces"});
      const int max_faces_ = max_faces(s);
      auto [z0, z1] = range(member(s, "z"), "'z'");
      const int sides = integer(member(s, "sides"), "'sides'");
      const double radius = positive(member(s, "radius"), "'radius'");
      return within_budget([&, z0 = z0, z1 = z1] { return regular_prism(sides, radius, z0, z1, max_faces_); },
                           note);
    }
    if (shape == "cylinder" || shape == "cone") {
      allow(s, {"radius", "z", "tolerance", "pixel_tolerance", "max_faces"});
      const int max_faces_ = max_faces(s);
      const double r = positive(member(s, "radius"), "'radius'");
      auto [z0, z1] = range(member(s, "z"), "'z'");
      const double half = std::abs(z1 - z0) / 2;
      const double tol = curved_tolerance(s, Vec3(0, 0, (z0 + z1) / 2), std::hypot(r, half), t, note);
      const int n = within_budget([&] { return segments_for_tolerance(r, tol); }, note);
      surface = shape == "cylinder" ? SmoothSurface::cylinder(r, z0, z1)
                                    : SmoothSurface::cone(r, z0, z1);
      Body body = within_budget(
          [&, z0 = z0, z1 = z1] {
            return shape == "cylinder" ? cylinder(r, z0, z1, tol, max_faces_) : cone(r, z0, z1, tol, max_faces_);
          },
          note);
      note = std::to_string(n) + " sides: " + note;
      return body;
    }
    if (shape == "sphere") {
      allow(s, {"center", "radius", "tolerance", "pixel_tolerance", "max_faces"});
      const int max_faces_ = max_faces(s);
      const Vec3 c = vec3(member(s, "center"), "'center'");
      const double r = positive(member(s, "radius"), "'radius'");
      const double tol = curved_tolerance(s, c, r, t, note);
      Body body = within_budget([&] { return sphere(c, r, tol, max_faces_); }, note);
      note = std::to_string(body.face_count()) + " faces: " + note;
      surface = SmoothSurface::sphere(c, r);
      return body;
    }
    if (shape == "mesh") {
      std::vector<Body> bodies = read_mesh(s);
      if (bodies.size() != 1)
        fail(s, "'" + s.string + "' holds " + std::to_string(bodies.size()) +
                    " bodies; a scene body takes a mesh of exactly one");
      return bodies[0];
    }
    if (shape == "polyhedron") {
      allow(s, {"vertices", "faces"});
      const JsonValue& vs = member(s, "vertices");
      const JsonValue& fs = member(s, "faces");
      if (vs.kind != Kind::Array) fail(vs, "'vertices' must be an array of [x, y, z]");
      if (fs.kind != Kind::Array) fail(fs, "'faces' must be an array");
      std::vector<Vec3> vertices;
      for (const JsonValue& p : vs.items) vertices.push_back(vec3(p, "a vertex"));
      std::vector<Face> faces;
      for (const JsonValue& f : fs.items) faces.push_back(read_face(f));
      return Body(std::move(vertices), std::move(faces));
    }
    // Boolean bodies over earlier names.
    if (s.kind != Kind::Array || s.items.size() != 2)
      fail(s, "'" + shape + "' takes two body names: [\"a\", \"b\"]");
    const Body& a = operand(s.items[0], scene);
    const Body& b = operand(s.items[1], scene);
    if (shape == "unite") return unite(a, b);
    std::optional<Body> r = shape == "subtract" ? subtract(a, b) : intersect(a, b);
    if (!r) fail(s, "the " + std::string(shape == "subtract" ? "difference" : "intersection") +
                        " is empty");
    return *r;
  }

  Face read_face(const JsonValue& f) const {
    if (f.kind != Kind::Array || f.items.empty())
      fail(f, "a face is an array of vertex indices, or an array of loops (outer, then holes)");
    auto loop = [&](const JsonValue& l) {
      if (l.kind != Kind::Array) fail(l, "a loop is an array of vertex indices");
      std::vector<int> ids;
      for (const JsonValue& i : l.items) ids.push_back(integer(i, "a vertex index"));
      return ids;
    };
    Face face;
    if (f.items[0].kind == Kind::Array) {
      for (const JsonValue& l : f.items) face.loops.push_back(loop(l));
    } else {
      face.loops.push_back(loop(f));
    }
    return face;
  }

  std::string path_;
  ReadOptions mesh_options_;  // how "mesh" bodies are imported
  std::map<std::string, std::optional<PolygonSoup>> open_meshes_;  // open_mesh's answers by path
  std::string context_;
  const Camera* camera_ = nullptr;
  const JsonValue* bodies_json_ = nullptr;
  std::optional<double> view_height_;
};

nlohmann::json vec_json(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

bool is_scene_path(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".json";
}

Scene parse_scene(const std::string& path, const std::string& text, double tolerance) {
  JsonValue root = parse_json(path, text);
  return SceneReader(path, tolerance).read(root);
}

Scene read_scene(const std::string& path, double tolerance) {
  return parse_scene(path, read_file(path), tolerance);
}

std::string format_scene(const Scene& scene) {
  nlohmann::ordered_json root;
  root["version"] = 1;
  nlohmann::ordered_json bodies = nlohmann::ordered_json::array();
  // A two-sided body (an open surface, Body::two_sided_surface, or one two-sided polygon) is
  // written as a "polyhedron" of its front faces, which the reader takes as an open surface
  // again.
  for (const SceneBody& sb : scene.bodies()) {
    nlohmann::ordered_json b;
    nlohmann::ordered_json vertices = nlohmann::ordered_json::array();
    nlohmann::ordered_json faces = nlohmann::ordered_json::array();
    if (sb.body.two_sided()) {
      b["name"] = sb.name;
      for (const Vec3& p : sb.body.vertices()) vertices.push_back({p.x(), p.y(), p.z()});
      for (int f = 0; f < sb.body.face_count() / 2; ++f) faces.push_back(sb.body.faces()[static_cast<size_t>(f)].loops[0]);
    } else {
      b["name"] = sb.name;
      for (const Vec3& p : sb.body.vertices()) vertices.push_back({p.x(), p.y(), p.z()});
      for (const Face& f : sb.body.faces())
        faces.push_back(f.loops.size() == 1 ? nlohmann::ordered_json(f.loops[0])
                                            : nlohmann::ordered_json(f.loops));
    }
    b["polyhedron"] = {{"vertices", vertices}, {"faces", faces}};
    const Material& m = sb.material;
    b["material"] = {{"color", {m.color.x(), m.color.y(), m.color.z()}},
                     {"ka", m.ka}, {"kd", m.kd}, {"ks", m.ks}, {"shininess", m.shininess}};
    if (sb.hidden) b["hidden"] = true;
    bodies.push_back(b);
  }
  root["bodies"] = bodies;
  const Camera& c = scene.camera;
  if (c.projection == Camera::Projection::Parallel)
    root["camera"] = {{"projection", "parallel"}, {"direction", vec_json(c.direction)},
                      {"up", vec_json(c.up)}};
  else
    root["camera"] = {{"projection", "perspective"}, {"eye", vec_json(c.eye)},
                      {"target", vec_json(c.target)}, {"up", vec_json(c.up)},
                      {"fov_deg", c.fov_deg}};
  nlohmann::ordered_json lights = nlohmann::ordered_json::array();
  for (const Light& l : scene.lights) {
    nlohmann::ordered_json j;
    switch (l.type) {
      case Light::Type::Directional:
        j = {{"type", "directional"}, {"direction", vec_json(l.direction)}};
        break;
      case Light::Type::Point:
        j = {{"type", "point"}, {"position", vec_json(l.position)}};
        break;
      case Light::Type::Spot:
        j = {{"type", "spot"}, {"position", vec_json(l.position)},
             {"direction", vec_json(l.direction)}, {"cone_deg", l.cone_deg}, {"falloff", l.falloff}};
        break;
      case Light::Type::Sun:
        j = {{"type", "sun"}, {"latitude", l.latitude}, {"longitude", l.longitude},
             {"time", l.time.to_string()}};
        break;
    }
    j["intensity"] = l.intensity;
    j["color"] = vec_json(l.color);
    lights.push_back(j);
  }
  root["lights"] = lights;
  root["image"] = {{"width", c.width}, {"height", c.height},
                   {"background", vec_json(scene.image.background)}};
  return root.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

void write_scene(const Scene& scene, const std::string& path) {
  write_file_atomically(path, format_scene(scene));
}

}  // namespace hedra::io
