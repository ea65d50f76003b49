#include "cli/info.h"

#include <algorithm>
#include <cstdio>

#include <filesystem>
#include <iomanip>

#include "cli/usage.h"
#include "hedra/io/mesh_io.h"
#include "hedra/io/scene_json.h"
#include "hedra/mesh/convexity.h"
#include "hedra/core/error.h"
#include "hedra/mesh/open_surface.h"

namespace hedra::cli {
namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

// The name column: at least 12 characters wide, left-aligned, longer names kept whole.
std::string pad(const std::string& name) {
  return name.size() >= 12 ? name : name + std::string(12 - name.size(), ' ');
}

// The table lists at most this many non-convex faces per body: a float32 mesh of a sphere has
// tens of thousands (rounding makes its diagonals reflex), which made one row of 200 KB.
constexpr size_t kListedFaces = 1000;

std::string join(const std::vector<int>& ids) {
  std::string s;
  const size_t shown = std::min(ids.size(), kListedFaces);
  for (size_t i = 0; i < shown; ++i) s += (i ? ", " : "") + std::to_string(ids[i]);
  if (shown < ids.size())
    s += ", … (" + std::to_string(ids.size()) + " in all; --json lists every one)";
  return s.empty() ? "-" : s;
}

}  // namespace

nlohmann::json info_json(const std::vector<NamedBody>& bodies, bool with_matrix) {
  nlohmann::json list = nlohmann::json::array();
  for (const NamedBody& nb : bodies) {
    const Body& b = nb.body;
    ConvexityReport c = convexity(b);
    nlohmann::json j = {{"name", nb.name},          {"vertices", b.vertex_count()},
                        {"edges", b.edge_count()},  {"faces", b.face_count()},
                        {"closed", true},           {"volume", b.volume()},
                        {"area", b.area()},         {"convex", c.convex},
                        {"nonconvex_faces", c.nonconvex_faces}};
    if (!nb.lod_note.empty()) j["lod"] = nb.lod_note;
    if (with_matrix || b.face_count() <= kSmallBodyFaces) {
      nlohmann::json columns = nlohmann::json::array();
      for (int f = 0; f < b.face_count(); ++f) {
        const Vec4& k = b.plane(f).coefficients;
        columns.push_back({k[0], k[1], k[2], k[3]});
      }
      j["matrix"] = columns;  // one (a, b, c, d) column per face
    }
    list.push_back(j);
  }
  return {{"bodies", list}};
}

void print_info_table(std::ostream& out, const std::vector<NamedBody>& bodies, bool with_matrix) {
  // The name and the list of non-convex faces have no length limit: they are written as
  // strings around the fixed-width columns, so a long row is never cut.
  char line[256];
  std::snprintf(line, sizeof line, "%8s %6s %6s %6s %14s %14s %6s  %s\n", "vertices", "edges",
                "faces", "closed", "volume", "area", "convex", "non-convex faces");
  out << pad(std::string("body")) << " " << line;
  for (const NamedBody& nb : bodies) {
    const Body& b = nb.body;
    ConvexityReport c = convexity(b);
    std::snprintf(line, sizeof line, "%8d %6d %6d %6s %14s %14s %6s  ", b.vertex_count(),
                  b.edge_count(), b.face_count(), "yes", num(b.volume()).c_str(),
                  num(b.area()).c_str(), c.convex ? "yes" : "no");
    out << pad(sanitize_message(nb.name)) << " " << line << join(c.nonconvex_faces) << "\n";
  }
  bool any_lod = false;
  for (const NamedBody& nb : bodies) {
    if (nb.lod_note.empty()) continue;
    if (!any_lod) out << "\nlevel of detail:\n";
    any_lod = true;
    out << "  " << sanitize_message(nb.name) << ": " << nb.lod_note << "\n";
  }
  for (const NamedBody& nb : bodies) {
    const Body& b = nb.body;
    if (!with_matrix && b.face_count() > kSmallBodyFaces) continue;
    out << "\nbody matrix of " << sanitize_message(nb.name) << " (4 x " << b.face_count()
        << "; column j = a, b, c, d of face j, inner normals):\n";
    for (int row = 0; row < 4; ++row) {
      out << "  " << "abcd"[row] << " ";
      for (int f = 0; f < b.face_count(); ++f) {
        std::snprintf(line, sizeof line, " %9.4g", b.matrix()(row, f));
        out << line;
      }
      out << "\n";
    }
  }
}

namespace {
double import_tolerance = 0;
}  // namespace

void set_import_tolerance(double tolerance) { import_tolerance = tolerance; }

std::vector<NamedBody> load_bodies(const std::string& path, std::vector<SceneSurface>* surfaces) {
  std::vector<NamedBody> named;
  if (io::is_scene_path(path)) {
    Scene scene = io::read_scene(path, import_tolerance);
    // Open surfaces are not solids: `info` reports them apart, the other commands refuse them.
    if (!scene.surfaces.empty() && !surfaces) throw InvalidInput(scene.surfaces[0].not_solid);
    if (surfaces) surfaces->insert(surfaces->end(), scene.surfaces.begin(), scene.surfaces.end());
    for (const SceneBody* b : scene.visible_bodies())
      if (!b->body.two_sided()) named.push_back({b->name, b->body, b->lod_note});
    return named;
  }
  io::ReadOptions options;
  options.merge.coplanar_tolerance = import_tolerance;
  std::vector<Body> bodies = io::read_bodies(path, options);
  const std::string stem = std::filesystem::path(path).stem().string();
  for (size_t i = 0; i < bodies.size(); ++i)
    named.push_back({bodies.size() == 1 ? stem : stem + "#" + std::to_string(i), bodies[i], ""});
  return named;
}

std::optional<SceneSurface> open_surface(const std::string& path) {
  if (io::is_scene_path(path)) return std::nullopt;
  const PolygonSoup soup = io::read_soup(path);
  for (const auto& poly : soup.polygons)
    for (int v : poly)
      if (v < 0 || static_cast<size_t>(v) >= soup.vertices.size()) return std::nullopt;
  SceneSurface out = SceneSurface::of(std::filesystem::path(path).stem().string(), soup);
  if (out.boundary_edges == 0) return std::nullopt;
  return out;
}

nlohmann::json open_surface_json(const SceneSurface& s) {
  return {{"name", s.name},        {"vertices", s.vertices},
          {"edges", s.edges},      {"faces", s.faces},
          {"closed", false},       {"boundary_edges", s.boundary_edges},
          {"first_boundary_edge", {s.first_from, s.first_to}},
          {"area", s.area}};
}

void print_open_surface(std::ostream& out, const SceneSurface& s, bool json) {
  if (json) {
    out << nlohmann::json{{"bodies", nlohmann::json::array({open_surface_json(s)})}}.dump(2) << "\n";
    return;
  }
  // Formatted with the name apart, so that a long name never cuts the row (see print_info_table).
  char line[160];
  std::snprintf(line, sizeof line, "%8s %6s %6s %6s %14s %14s\n", "vertices", "edges", "faces",
                "closed", "boundary edges", "area");
  out << std::left << std::setw(12) << "surface" << ' ' << line;
  std::snprintf(line, sizeof line, "%8d %6d %6d %6s %14d %14s\n", s.vertices, s.edges, s.faces, "no",
                s.boundary_edges, num(s.area).c_str());
  out << std::setw(12) << s.name << std::right << ' ' << line;
  out << "open surface, not a solid (decompose, clip and convert need a closed body; hlr, shadows "
         "and render take it as two-sided faces): first boundary edge between vertices "
      << s.first_from << " and " << s.first_to << "\n";
}

Scene load_scene(const std::string& path) {
  if (io::is_scene_path(path)) return io::read_scene(path, import_tolerance);
  Scene scene;
  std::vector<NamedBody> bodies;
  try {
    bodies = load_bodies(path);
  } catch (const InvalidInput&) {
    // An open surface (a scan, a terrain, a single face) is not a solid, but hidden lines,
    // shadows and rendering take it as two-sided convex faces (hedra/mesh/open_surface.h),
    // one scene body of them all (Body::two_sided_surface), named <stem>.
    // Taken as a surface when it has boundary edges and each directed edge once (consistently
    // oriented, no edge shared by three faces); a flipped face of a solid stays an error.
    const PolygonSoup soup = io::read_soup(path);
    if (!is_open_surface(soup)) throw;
    try {
      bodies.push_back({std::filesystem::path(path).stem().string(), two_sided_surface(soup, import_tolerance), ""});
    } catch (const InvalidInput& inner) {
      throw InvalidInput(path + ": open surface: " + inner.what());
    }
  }
  for (const NamedBody& nb : bodies) scene.add(nb.name, nb.body);
  scene.camera = Camera::parallel({-1, -2, -1.5}, {0, 0, 1});
  scene.lights.push_back(Light::directional({-1, -1.5, -3}, 0.9));
  return scene;
}

}  // namespace hedra::cli
