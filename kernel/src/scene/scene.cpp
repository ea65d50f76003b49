#include "hedra/scene/scene.h"

#include <cmath>

#include "hedra/core/error.h"

namespace hedra {

SceneSurface SceneSurface::of(const std::string& name, const PolygonSoup& soup) {
  const SurfaceSummary summary = summarize_surface(soup);
  SceneSurface out;
  out.name = name;
  out.vertices = summary.vertices;
  out.edges = summary.edges;
  out.faces = summary.faces;
  out.boundary_edges = summary.boundary.boundary_edges;
  out.first_from = summary.boundary.first_from;
  out.first_to = summary.boundary.first_to;
  out.area = summary.area;
  return out;
}

void Material::validate() const {
  auto fail = [](const std::string& m) { throw InvalidInput("material: " + m); };
  if (!color.allFinite() || (color.array() < 0).any() || (color.array() > 1).any())
    fail("'color' components must lie in [0, 1]");
  for (double k : {ka, kd, ks})
    if (!(k >= 0 && k <= 1)) fail("'ka', 'kd' and 'ks' must lie in [0, 1]");
  if (!(shininess >= 0) || !std::isfinite(shininess)) fail("'shininess' must be >= 0");
}

SceneBody& Scene::add(const std::string& name, const Body& body, const Material& material) {
  if (name.empty()) throw InvalidInput("a body needs a non-empty name");
  if (contains(name)) throw InvalidInput("body name '" + name + "' is used twice");
  material.validate();
  index_.emplace(name, bodies_.size());
  bodies_.push_back({name, body, material, false, "", SmoothSurface()});
  return bodies_.back();
}

bool Scene::contains(const std::string& name) const { return index_.contains(name); }

const SceneBody& Scene::get(const std::string& name) const {
  const auto it = index_.find(name);
  if (it == index_.end()) throw InvalidInput("no body named '" + name + "'");
  return bodies_[it->second];
}

std::vector<const SceneBody*> Scene::visible_bodies() const {
  std::vector<const SceneBody*> out;
  for (const SceneBody& b : bodies_)
    if (!b.hidden) out.push_back(&b);
  return out;
}

Eigen::AlignedBox3d Scene::bbox() const {
  Eigen::AlignedBox3d box;
  box.setEmpty();
  for (const SceneBody* b : visible_bodies()) box.extend(b->body.bbox());
  return box;
}

}  // namespace hedra
