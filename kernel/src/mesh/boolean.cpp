#include "hedra/mesh/boolean.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <numeric>
#include <string>
#include <unordered_map>

#include "core/exact_solid.h"
#include "hedra/core/error.h"
#include "mesh/union_find.h"

namespace hedra {
namespace {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<EK::Point_3>;
using FaceIndex = Mesh::Face_index;
namespace PMP = CGAL::Polygon_mesh_processing;

// Name of the face property that records, for every triangle of an operand and of the result,
// the input face it lies in (operand A's faces first, then B's).
constexpr const char* kOrigin = "f:hedra_origin";

// The body's exact solid where it keeps one (a Boolean's result: the next Boolean starts from
// the exact corners, not their rounding), else its triangles with their double corners.
Mesh to_mesh(const Body& body, int first_face) {
  Mesh mesh;
  std::vector<Mesh::Vertex_index> ids;
  if (body.exact_solid()) {
    const internal::ExactSolid& solid = internal::materialized(*body.exact_solid());
    ids.reserve(solid.points.size());
    for (const EK::Point_3& p : solid.points) ids.push_back(mesh.add_vertex(p));
    auto origin = mesh.add_property_map<FaceIndex, int>(kOrigin, -1).first;
    for (const internal::ExactSolid::Tri& t : solid.triangles) {
      FaceIndex f = mesh.add_face(ids[t.v[0]], ids[t.v[1]], ids[t.v[2]]);
      origin[f] = first_face + t.face;
    }
    return mesh;
  }
  ids.reserve(body.vertices().size());
  for (const Vec3& p : body.vertices()) ids.push_back(mesh.add_vertex(EK::Point_3(p.x(), p.y(), p.z())));
  auto origin = mesh.add_property_map<FaceIndex, int>(kOrigin, -1).first;
  for (const Triangle& t : body.triangles()) {
    FaceIndex f = mesh.add_face(ids[t.v[0]], ids[t.v[1]], ids[t.v[2]]);
    origin[f] = first_face + t.face;
  }
  return mesh;
}

// Carries the origin of every triangle through corefinement: a triangle split into subfaces
// passes its origin on to them, and a triangle copied into the output keeps it.
struct OriginVisitor : PMP::Corefinement::Default_visitor<Mesh> {
  int current = -1;
  static Mesh::Property_map<FaceIndex, int> origin(const Mesh& m) {
    return m.property_map<FaceIndex, int>(kOrigin).first;
  }
  void before_subface_creations(FaceIndex f, Mesh& tm) { current = origin(tm)[f]; }
  void after_subface_created(FaceIndex f, Mesh& tm) { origin(tm)[f] = current; }
  void after_face_copy(FaceIndex from, const Mesh& source, FaceIndex to, Mesh& target) {
    origin(target)[to] = origin(source)[from];
  }
};

using internal::UnionFind;

// Exact signed area of a loop, twice, projected along coordinate axis `axis` (right-handed
// about that axis).
// Summed in the exact number type: a lazy sum built one node per term recurses once per term
// when evaluated (a stack overflow for loops of many thousand points).
EK::FT::ET projected_area2(const std::vector<const EK::Point_3*>& loop, int axis) {
  const int u = (axis + 1) % 3, w = (axis + 2) % 3;
  EK::FT::ET sum = 0;
  for (size_t i = 0; i < loop.size(); ++i) {
    const EK::Point_3& a = *loop[i];
    const EK::Point_3& b = *loop[(i + 1) % loop.size()];
    sum += CGAL::exact(a.cartesian(u)) * CGAL::exact(b.cartesian(w)) -
           CGAL::exact(b.cartesian(u)) * CGAL::exact(a.cartesian(w));
  }
  return sum;
}

// The exact result to a body. All grouping decisions are made on the exact triangles, before
// any coordinate is rounded:
//  - neighbouring triangles lying in one input face (recorded through corefinement) form one
//    face, so a face of an operand that is planar only within rounding (a rotated box, the
//    quads of a sphere) comes back as one face, not as triangles bent by a few ulps;
//  - neighbouring triangles in exactly the same oriented plane form one face too (the shared
//    top of two united boxes);
//  - a vertex that only two faces share lies on the line where they meet and only splits an
//    edge (corefinement leaves them): dropped, whatever its coordinates round to.
// Each face is then one loop set traced on the exact mesh; only the surviving vertices are
// rounded to double, once. Rounding moves a vertex by at most half an ulp per coordinate,
// which keeps faces planar within kRoundingPlanarity. A region whose boundary touches itself
// keeps its triangles. Cost O(n log n) for n result triangles.
std::optional<Body> to_body(const Mesh& mesh) {
  if (mesh.number_of_faces() == 0) return std::nullopt;
  auto [origin, has_origin] = mesh.property_map<FaceIndex, int>(kOrigin);
  std::vector<FaceIndex> faces(mesh.faces().begin(), mesh.faces().end());
  std::unordered_map<std::size_t, int> face_id;
  for (size_t i = 0; i < faces.size(); ++i) face_id[static_cast<std::size_t>(faces[i])] = static_cast<int>(i);
  const int n = static_cast<int>(faces.size());

  // Regions: union of neighbours with one origin or one exact oriented plane.
  UnionFind regions(n);
  for (Mesh::Edge_index e : mesh.edges()) {
    Mesh::Halfedge_index h = mesh.halfedge(e), g = mesh.opposite(h);
    if (mesh.is_border(h) || mesh.is_border(g)) continue;
    const int a = face_id[static_cast<std::size_t>(mesh.face(h))];
    const int b = face_id[static_cast<std::size_t>(mesh.face(g))];
    bool same = has_origin && origin[faces[a]] >= 0 && origin[faces[a]] == origin[faces[b]];
    if (!same) {
      const EK::Point_3& u = mesh.point(mesh.source(h));
      const EK::Point_3& v = mesh.point(mesh.target(h));
      const EK::Point_3& p = mesh.point(mesh.target(mesh.next(h)));
      const EK::Point_3& q = mesh.point(mesh.target(mesh.next(g)));
      same = CGAL::coplanar(u, v, p, q) && CGAL::coplanar_orientation(u, v, p, q) == CGAL::NEGATIVE;
    }
    if (same) regions.unite(a, b);
  }

  // Vertices: index and the number of distinct regions around each.
  std::unordered_map<std::size_t, int> vertex_id;
  std::vector<Mesh::Vertex_index> vertex_of;
  for (Mesh::Vertex_index v : mesh.vertices()) {
    vertex_id[static_cast<std::size_t>(v)] = static_cast<int>(vertex_of.size());
    vertex_of.push_back(v);
  }
  auto vid = [&](Mesh::Vertex_index v) { return vertex_id.at(static_cast<std::size_t>(v)); };

  // Each region's boundary half-edges (from -> to), traced into loops.
  std::vector<int> root(n);
  for (int i = 0; i < n; ++i) root[i] = regions.find(i);
  std::unordered_map<int, std::vector<int>> members;
  std::vector<int> order;  // regions in order of their first triangle
  for (int i = 0; i < n; ++i) {
    auto [it, inserted] = members.try_emplace(root[i]);
    if (inserted) order.push_back(root[i]);
    it->second.push_back(i);
  }
  std::vector<Face> out_faces;
  std::vector<int> face_region;  // region of each output face
  std::vector<int> face_of(n, -1);  // output face of each triangle
  for (int r : order) {
    std::unordered_map<int, int> next;
    std::vector<std::pair<int, int>> boundary;
    bool pinched = false;
    Vec3 normal = Vec3::Zero();
    for (int i : members[r]) {
      Mesh::Halfedge_index h0 = mesh.halfedge(faces[i]), h = h0;
      std::array<Vec3, 3> p;
      int k = 0;
      do {
        const EK::Point_3& q = mesh.point(mesh.target(h));
        p[k++] = Vec3(CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z()));
        Mesh::Halfedge_index g = mesh.opposite(h);
        const bool inner = !mesh.is_border(g) && root[face_id[static_cast<std::size_t>(mesh.face(g))]] == r;
        if (!inner) {
          const int a = vid(mesh.source(h)), b = vid(mesh.target(h));
          if (!next.emplace(a, b).second) pinched = true;
          boundary.emplace_back(a, b);
        }
        h = mesh.next(h);
      } while (h != h0);
      normal += (p[1] - p[0]).cross(p[2] - p[0]);
    }
    std::vector<std::vector<int>> loops;
    int outers = 0;
    if (!pinched) {
      int axis = 0;
      normal.cwiseAbs().maxCoeff(&axis);
      std::unordered_map<int, char> used;
      for (const auto& [a0, b0] : boundary) {
        if (used[a0]) continue;
        std::vector<int> loop;
        int a = a0;
        while (!used[a]) {
          used[a] = 1;
          loop.push_back(a);
          a = next.at(a);
        }
        if (a != a0) {
          pinched = true;
          break;
        }
        std::vector<const EK::Point_3*> pts;
        for (int w : loop) pts.push_back(&mesh.point(vertex_of[w]));
        const CGAL::Sign s = CGAL::sign(projected_area2(pts, axis));
        const bool outer = (normal[axis] > 0) == (s == CGAL::POSITIVE);
        if (s == CGAL::ZERO) pinched = true;
        outers += outer;
        if (outer) loops.insert(loops.begin(), std::move(loop));
        else loops.push_back(std::move(loop));
      }
    }
    if (pinched || outers != 1) {
      for (int i : members[r]) {
        std::vector<int> tri;
        for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(faces[i]), mesh))
          tri.push_back(vid(v));
        face_of[i] = static_cast<int>(out_faces.size());
        out_faces.emplace_back(std::move(tri));
        face_region.push_back(r);
      }
    } else {
      for (int i : members[r]) face_of[i] = static_cast<int>(out_faces.size());
      out_faces.emplace_back(std::move(loops));
      face_region.push_back(r);
    }
  }

  // Vertices on the boundary of exactly two faces (of two regions) only split an edge.
  const size_t nv = vertex_of.size();
  std::vector<int> faces_at(nv, 0), region_a(nv, -1), region_b(nv, -1);
  for (size_t f = 0; f < out_faces.size(); ++f)
    for (const auto& loop : out_faces[f].loops)
      for (int w : loop) {
        ++faces_at[w];
        if (region_a[w] < 0) region_a[w] = face_region[f];
        else if (region_b[w] < 0) region_b[w] = face_region[f];
      }
  std::vector<char> removable(nv, 0);
  for (size_t w = 0; w < nv; ++w)
    removable[w] = faces_at[w] == 2 && region_b[w] >= 0 && region_a[w] != region_b[w];
  for (bool changed = true; changed;) {  // every loop keeps three vertices
    changed = false;
    for (const Face& face : out_faces)
      for (const auto& loop : face.loops) {
        size_t kept = 0;
        for (int w : loop) kept += !removable[w];
        if (kept >= 3) continue;
        for (int w : loop)
          if (removable[w]) {
            removable[w] = 0;
            changed = true;
          }
      }
  }

  // Round the survivors once; vertices keep the mesh's order.
  std::vector<int> remap(nv, -1);
  for (Face& face : out_faces)
    for (auto& loop : face.loops) {
      std::erase_if(loop, [&](int w) { return removable[w] != 0; });
      for (int w : loop) remap[w] = 0;
    }
  std::vector<Vec3> vertices;
  for (size_t w = 0; w < nv; ++w)
    if (remap[w] == 0) {
      remap[w] = static_cast<int>(vertices.size());
      const EK::Point_3& p = mesh.point(vertex_of[w]);
      vertices.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
    }
  for (Face& face : out_faces)
    for (auto& loop : face.loops)
      for (int& w : loop) w = remap[w];
  Body body(std::move(vertices), std::move(out_faces));
  // The exact mesh stays with its rounding: every vertex (those only splitting an edge too),
  // each triangle with the face it rounds into.
  auto solid = std::make_shared<internal::ExactSolid>();
  solid->points.reserve(nv);
  // A corner whose exact coordinates are doubles is stored as those doubles: a constructed
  // point's interval need not be a point even then, and later tests take the fast path on
  // points with double coordinates (decompose, `side()`).
  solid->rounded = false;
  for (size_t w = 0; w < nv; ++w) {
    const EK::Point_3& p = mesh.point(vertex_of[w]);
    const auto& e = CGAL::exact(p);
    const double x = CGAL::to_double(e.x()), y = CGAL::to_double(e.y()), z = CGAL::to_double(e.z());
    if (e.x() == x && e.y() == y && e.z() == z) {
      solid->points.emplace_back(x, y, z);
    } else {
      solid->points.push_back(p);
      if (remap[w] >= 0) solid->rounded = true;  // a corner of the body, rounded
    }
  }
  bool identity = true;
  for (size_t w = 0; w < nv && identity; ++w) identity = remap[w] == static_cast<int>(w);
  if (!identity) solid->body_vertex = std::move(remap);
  solid->triangles.reserve(faces.size());
  for (int i = 0; i < n; ++i) {
    internal::ExactSolid::Tri t{{}, face_of[i]};
    int k = 0;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(faces[i]), mesh)) t.v[k++] = vid(v);
    solid->triangles.push_back(t);
  }
  internal::attach_exact_solid(body, std::move(solid));
  return body;
}

enum class Op { Union, Difference, Intersection };

std::optional<Body> boolean(const Body& a, const Body& b, Op op, const char* name) {
  Mesh ma = to_mesh(a, 0), mb = to_mesh(b, a.face_count()), out;
  out.add_property_map<FaceIndex, int>(kOrigin, -1);
  OriginVisitor visitor;
  const auto np = CGAL::parameters::visitor(visitor);
  const auto none = CGAL::parameters::default_values();
  bool ok = false;
  switch (op) {
    case Op::Union: ok = PMP::corefine_and_compute_union(ma, mb, out, np, none, none); break;
    case Op::Difference: ok = PMP::corefine_and_compute_difference(ma, mb, out, np, none, none); break;
    case Op::Intersection: ok = PMP::corefine_and_compute_intersection(ma, mb, out, np, none, none); break;
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

Sign exact_volume_sign(const std::vector<std::pair<int, Body>>& terms) {
  EK::FT::ET sum = 0;
  for (const auto& [k, body] : terms) sum += EK::FT::ET(k) * internal::six_volume(body);
  return static_cast<Sign>(CGAL::sign(sum));
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
