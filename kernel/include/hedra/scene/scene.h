// A scene: named bodies with materials, one camera, any number of lights.
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include "hedra/core/body.h"
#include "hedra/mesh/open_surface.h"
#include "hedra/scene/camera.h"
#include "hedra/scene/light.h"
#include "hedra/core/smooth_surface.h"

namespace hedra {

/// Phong material (docs/algorithms.md §8): colour per channel, ambient, diffuse and specular
/// coefficients and the specular exponent.
struct Material {
  Vec3 color = Vec3(0.8, 0.8, 0.8);
  double ka = 0.2, kd = 0.7, ks = 0.2, shininess = 20;
  bool operator==(const Material&) const = default;
  /// \throw InvalidInput naming the field.
  void validate() const;
};

struct SceneBody {
  std::string name;
  Body body;
  Material material;
  /// Hidden bodies (Boolean operands) are kept for reference but are not part of the scene.
  bool hidden = false;
  /// For curved primitives: how the tessellation was chosen ("chordal tolerance 0.01").
  std::string lod_note;
  /// For curved primitives: the analytic surface, whose normals smooth shading uses
  /// (hedra/render/raster.h). None for every other body: all faces shade flat.
  SmoothSurface surface;

  SceneBody& with_material(const Material& m) { material = m; return *this; }
  SceneBody& with_color(const Vec3& c) { material.color = c; return *this; }
  SceneBody& hide() { hidden = true; return *this; }
  SceneBody& with_surface(const SmoothSurface& s) { surface = s; return *this; }
};

/// An open surface of a scene file (a scan, a terrain: a "mesh" or "polyhedron" body that is
/// not closed). Hidden lines, shadows and rendering take it as one scene body of that name,
/// a Body::two_sided_surface; solid commands refuse it with `not_solid`.
struct SceneSurface {
  std::string name;       ///< the body's name in the scene file
  std::string not_solid;  ///< one-line message naming the file, the body and the first boundary edge
  int vertices = 0, edges = 0, faces = 0, boundary_edges = 0;
  int first_from = -1, first_to = -1;  ///< first boundary edge (vertex numbers of the input)
  double area = 0;
  /// The counts of `soup` (summarize_surface: vertices used, edges, faces, boundary, area) under
  /// `name`; not_solid empty. \pre every index in range. Cost O(n log n).
  static SceneSurface of(const std::string& name, const PolygonSoup& soup);
};

struct ImageSettings {
  Vec3 background = Vec3(1, 1, 1);
};

/// \code
///   Scene scene;
///   scene.add("ground", box({0, 0, -1}, {100, 100, 0}));
///   scene.add("tower", box({0, 0, 0}, {2, 2, 10}).rotated_z(30).translated({5, 0, 0}))
///        .with_color({0.8, 0.3, 0.2});
///   scene.camera = Camera::perspective({30, -40, 25}, {5, 5, 0}, 40);
///   scene.lights.push_back(Light::sun(52.5, 13.4, UtcTime::parse("2026-06-21T10:00:00Z")));
/// \endcode
class Scene {
 public:
  /// Adds a body under a new name and returns it for chained settings (its name is fixed: the
  /// scene finds bodies by it). \throw InvalidInput when the name is empty or already used.
  /// Cost O(1) expected (names are hashed).
  SceneBody& add(const std::string& name, const Body& body, const Material& material = {});
  /// \throw InvalidInput when there is no body of that name. Cost O(1) expected.
  const SceneBody& get(const std::string& name) const;
  bool contains(const std::string& name) const;
  const std::vector<SceneBody>& bodies() const { return bodies_; }
  /// Bodies that are part of the scene (not hidden), in order.
  std::vector<const SceneBody*> visible_bodies() const;
  /// Bounding box of the visible bodies.
  Eigen::AlignedBox3d bbox() const;

  Camera camera = Camera::course_default();
  std::vector<Light> lights;
  ImageSettings image;
  /// Open surfaces read from a scene file, in file order (each is one of bodies()).
  std::vector<SceneSurface> surfaces;

 private:
  std::vector<SceneBody> bodies_;
  std::unordered_map<std::string, size_t> index_;  // name → position in bodies_
};

}  // namespace hedra
