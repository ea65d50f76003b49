#include "cli/info.h"

#include <cstdio>

#include <filesystem>

#include "cli/usage.h"
#include "hedra/io/mesh_io.h"
#include "hedra/io/scene_json.h"
#include "hedra/mesh/convexity.h"

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

std::string join(const std::vector<int>& ids) {
  std::string s;
  for (size_t i = 0; i < ids.size(); ++i) s += (i ? ", " : "") + std::to_string(ids[i]);
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

std::vector<NamedBody> load_bodies(const std::string& path, double coplanar_tolerance,
                                   double planarity_tolerance) {
  std::vector<NamedBody> named;
  if (io::is_scene_path(path)) {
    Scene scene = io::read_scene(path);
    for (const SceneBody* b : scene.visible_bodies()) named.push_back({b->name, b->body, b->lod_note});
    return named;
  }
  io::ReadOptions options;
  options.merge.coplanar_tolerance = coplanar_tolerance;
  options.merge.planarity_tolerance = planarity_tolerance;
  std::vector<Body> bodies = io::read_bodies(path, options);
  const std::string stem = std::filesystem::path(path).stem().string();
  for (size_t i = 0; i < bodies.size(); ++i)
    named.push_back({bodies.size() == 1 ? stem : stem + "#" + std::to_string(i), bodies[i], ""});
  return named;
}

Scene load_scene(const std::string& path) {
  if (io::is_scene_path(path)) return io::read_scene(path);
  Scene scene;
  for (const NamedBody& nb : load_bodies(path)) scene.add(nb.name, nb.body);
  scene.camera = Camera::parallel({-1, -2, -1.5}, {0, 0, 1});
  scene.lights.push_back(Light::directional({-1, -1.5, -3}, 0.9));
  return scene;
}

}  // namespace hedra::cli
