#include "hedra/mesh/boolean.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <map>

#include "hedra/core/error.h"
#include "hedra/mesh/merge_coplanar.h"

namespace hedra {
namespace {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<EK::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

Mesh to_mesh(const Body& body) {
  Mesh mesh;
  std::vector<Mesh::Vertex_index> ids;
  ids.reserve(body.vertices().size());
  for (const Vec3& p : body.vertices()) ids.push_back(mesh.add_vertex(EK::Point_3(p.x(), p.y(), p.z())));
  for (const Triangle& t : body.triangles()) mesh.add_face(ids[t.v[0]], ids[t.v[1]], ids[t.v[2]]);
  return mesh;
}

// Exact result to body: triangles grouped by their exact oriented supporting plane, rounded to
// double only after the grouping.
std::optional<Body> to_body(const Mesh& mesh) {
  if (mesh.number_of_faces() == 0) return std::nullopt;
  PolygonSoup soup;
  std::map<Mesh::Vertex_index, int> index;
  for (Mesh::Vertex_index v : mesh.vertices()) {
    index[v] = static_cast<int>(soup.vertices.size());
    const EK::Point_3& p = mesh.point(v);
    soup.vertices.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
  }
  std::vector<EK::Plane_3> planes;
  std::vector<int> plane_ids;
  for (Mesh::Face_index f : mesh.faces()) {
    std::vector<int> poly;
    std::vector<EK::Point_3> pts;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      poly.push_back(index[v]);
      pts.push_back(mesh.point(v));
    }
    EK::Plane_3 plane(pts[0], pts[1], pts[2]);
    // Oriented plane equality is exact; the list of distinct planes stays short.
    int id = -1;
    for (size_t k = 0; k < planes.size() && id < 0; ++k)
      if (planes[k] == plane) id = static_cast<int>(k);
    if (id < 0) {
      id = static_cast<int>(planes.size());
      planes.push_back(plane);
    }
    plane_ids.push_back(id);
    soup.polygons.push_back(std::move(poly));
  }
  std::vector<Body> bodies = bodies_from_soup(soup, plane_ids);
  if (bodies.size() == 1) return bodies[0];
  // Several components: one body with several shells.
  std::vector<Vec3> vertices;
  std::vector<Face> faces;
  for (const Body& b : bodies) {
    const int base = static_cast<int>(vertices.size());
    vertices.insert(vertices.end(), b.vertices().begin(), b.vertices().end());
    for (Face f : b.faces()) {
      for (auto& loop : f.loops)
        for (int& v : loop) v += base;
      faces.push_back(std::move(f));
    }
  }
  return Body(std::move(vertices), std::move(faces));
}

enum class Op { Union, Difference, Intersection };

std::optional<Body> boolean(const Body& a, const Body& b, Op op, const char* name) {
  Mesh ma = to_mesh(a), mb = to_mesh(b), out;
  bool ok = false;
  switch (op) {
    case Op::Union: ok = PMP::corefine_and_compute_union(ma, mb, out); break;
    case Op::Difference: ok = PMP::corefine_and_compute_difference(ma, mb, out); break;
    case Op::Intersection: ok = PMP::corefine_and_compute_intersection(ma, mb, out); break;
  }
  if (!ok)
    throw InvalidInput(std::string(name) +
                       ": the result is not a manifold solid (the bodies touch along an edge or "
                       "at a vertex only?)");
  return to_body(out);
}

}  // namespace

Body unite(const Body& a, const Body& b) { return *boolean(a, b, Op::Union, "unite"); }

std::optional<Body> subtract(const Body& a, const Body& b) {
  return boolean(a, b, Op::Difference, "subtract");
}

std::optional<Body> intersect(const Body& a, const Body& b) {
  return boolean(a, b, Op::Intersection, "intersect");
}

std::optional<Body> intersect_convex(const Body& a, const Body& b) {
  // Inner half-spaces a·x + b·y + c·z + d >= 0 of both bodies, as exact planes.
  std::vector<EK::Plane_3> planes;
  for (const Body* body : {&a, &b})
    for (int f = 0; f < body->face_count(); ++f) {
      const Vec4& k = body->plane(f).coefficients;
      planes.emplace_back(k[0], k[1], k[2], k[3]);
    }
  // Vertex enumeration: every triple of planes meeting in one point inside all half-spaces.
  std::vector<EK::Point_3> points;
  const size_t n = planes.size();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      for (size_t k = j + 1; k < n; ++k) {
        auto hit = CGAL::intersection(planes[i], planes[j], planes[k]);
        if (!hit) continue;
        const EK::Point_3* p = boost::get<EK::Point_3>(&*hit);
        if (!p) continue;
        bool inside = true;
        for (size_t m = 0; m < n && inside; ++m)
          if (planes[m].oriented_side(*p) == CGAL::ON_NEGATIVE_SIDE) inside = false;
        if (inside) points.push_back(*p);
      }
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 4) return std::nullopt;
  // A solid needs four points not in one plane.
  size_t i2 = 2;
  while (i2 < points.size() && CGAL::collinear(points[0], points[1], points[i2])) ++i2;
  if (i2 == points.size()) return std::nullopt;
  bool solid = false;
  for (size_t i = 2; i < points.size() && !solid; ++i)
    solid = !CGAL::coplanar(points[0], points[1], points[i2], points[i]);
  if (!solid) return std::nullopt;
  Mesh hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  if (CGAL::is_closed(hull) && hull.number_of_faces() >= 4) return to_body(hull);
  return std::nullopt;
}

}  // namespace hedra
