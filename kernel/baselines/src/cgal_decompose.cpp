// CGAL's convex_decomposition_3 as a comparison method (Nef polyhedra are heavy to compile:
// this translation unit holds nothing else).
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_decomposition_3.h>

#include <map>

#include "hedra/baselines/decompose_baselines.h"
#include "hedra/core/error.h"
#include "hedra/mesh/merge_coplanar.h"

namespace hedra {
namespace {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using Nef = CGAL::Nef_polyhedron_3<EK>;
using Polyhedron = CGAL::Polyhedron_3<EK>;
using Mesh = CGAL::Surface_mesh<EK::Point_3>;

Body body_of(const Polyhedron& p) {
  PolygonSoup soup;
  std::map<Polyhedron::Vertex_const_handle, int> index;
  for (auto v = p.vertices_begin(); v != p.vertices_end(); ++v) {
    index[v] = static_cast<int>(soup.vertices.size());
    soup.vertices.emplace_back(CGAL::to_double(v->point().x()), CGAL::to_double(v->point().y()),
                               CGAL::to_double(v->point().z()));
  }
  std::vector<EK::Plane_3> planes;
  std::vector<int> ids;
  for (auto f = p.facets_begin(); f != p.facets_end(); ++f) {
    std::vector<int> poly;
    std::vector<EK::Point_3> pts;
    auto h = f->facet_begin();
    do {
      poly.push_back(index[h->vertex()]);
      pts.push_back(h->vertex()->point());
    } while (++h != f->facet_begin());
    // Nef facets can have collinear corners; the plane through the first non-collinear triple.
    size_t k = 2;
    while (k < pts.size() && CGAL::collinear(pts[0], pts[1], pts[k])) ++k;
    EK::Plane_3 plane(pts[0], pts[1], pts[k % pts.size()]);
    int id = -1;
    for (size_t i = 0; i < planes.size() && id < 0; ++i)
      if (planes[i] == plane) id = static_cast<int>(i);
    if (id < 0) {
      id = static_cast<int>(planes.size());
      planes.push_back(plane);
    }
    ids.push_back(id);
    soup.polygons.push_back(std::move(poly));
  }
  return bodies_from_soup(soup, ids).at(0);
}

}  // namespace

Decomposition decompose_cgal(const Body& body) {
  Mesh mesh;
  std::vector<Mesh::Vertex_index> ids;
  for (const Vec3& p : body.vertices()) ids.push_back(mesh.add_vertex(EK::Point_3(p.x(), p.y(), p.z())));
  for (const Triangle& t : body.triangles()) mesh.add_face(ids[t.v[0]], ids[t.v[1]], ids[t.v[2]]);
  Nef nef(mesh);
  CGAL::convex_decomposition_3(nef);
  Decomposition out;
  // Volume 0 is the outer volume; marked volumes are the pieces.
  auto volume = nef.volumes_begin();
  for (++volume; volume != nef.volumes_end(); ++volume) {
    if (!volume->mark()) continue;
    Polyhedron piece;
    nef.convert_inner_shell_to_polyhedron(volume->shells_begin(), piece);
    try {
      out.pieces.push_back(body_of(piece));
    } catch (const InvalidInput&) {
      ++out.degenerate_pieces;  // a sliver whose exact corners collapse when rounded
    }
  }
  return out;
}

}  // namespace hedra
