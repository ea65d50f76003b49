// The only translation unit that instantiates CGAL's box intersection and triangle tests for
// validation (compile time: these templates are heavy).
#include "hedra/mesh/self_intersection.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <array>
#include <tuple>

#include "hedra/core/parallel.h"
#include <CGAL/intersections.h>

#include <algorithm>
#include <cstdio>
#include <functional>

#include "hedra/core/error.h"

namespace hedra {
namespace {

// Epick: exact (filtered) predicates. Only predicates decide; the one construction below
// (a point for the message) is rounded and decides nothing.
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Tri = K::Triangle_3;
using Seg = K::Segment_3;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int,
                                                       CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;

// Stops the box traversal at the first intersecting pair.
struct Found {};

struct Input {
  const std::vector<Vec3>& vertices;
  const std::vector<std::array<int, 3>>& triangles;
  const std::vector<int>* face_of;  // null: each triangle is its own face
  // Whether segment ab is an edge of both faces (the mesh's own shared edge); null: always.
  std::function<bool(int a, int b, int fa, int fb)> shared_edge;
};

Point point(const Input& in, int v) {
  const Vec3& p = in.vertices[static_cast<size_t>(v)];
  return {p.x(), p.y(), p.z()};
}

Tri triangle(const Input& in, int t) {
  const auto& v = in.triangles[static_cast<size_t>(t)];
  return {point(in, v[0]), point(in, v[1]), point(in, v[2])};
}

int face(const Input& in, int t) { return in.face_of ? (*in.face_of)[static_cast<size_t>(t)] : t; }

// Whether triangles s and t (of different faces) meet anywhere but in what the mesh says they
// share. The case analysis of CGAL's Polygon_mesh_processing::self_intersections
// (do_faces_intersect), extended to vertices shared through a face's diagonal.
bool intersect(const Input& in, int s, int t) {
  const auto& a = in.triangles[static_cast<size_t>(s)];
  const auto& b = in.triangles[static_cast<size_t>(t)];
  int shared = 0, ia[3], ib[3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[i] == b[j]) { ia[shared] = i; ib[shared] = j; ++shared; }
  if (shared == 3) return true;  // the same triangle in two faces
  if (shared == 2) {
    const int p = a[ia[0]], q = a[ia[1]];
    // Segment pq lies in both triangles. It is fine only as the edge the two faces share
    // across; inside a face (a diagonal) it is a place where the surface touches itself.
    if (in.shared_edge && !in.shared_edge(p, q, face(in, s), face(in, t))) return true;
    const int r = a[3 - ia[0] - ia[1]], u = b[3 - ib[0] - ib[1]];
    // Two planes through pq meet only in pq; coplanar triangles overlap when their third
    // vertices lie on the same side of pq (a fold).
    return CGAL::coplanar(point(in, p), point(in, q), point(in, r), point(in, u)) &&
           CGAL::coplanar_orientation(point(in, p), point(in, q), point(in, r), point(in, u)) ==
               CGAL::POSITIVE;
  }
  if (shared == 1) {
    // Each triangle meets the other's plane in a segment from the shared vertex (or only the
    // vertex); two such segments on one line overlap beyond the vertex exactly when the
    // shorter one's far end, on its triangle's opposite edge, lies in the other triangle.
    const int i = ia[0], j = ib[0];
    const Seg opposite_a(point(in, a[(i + 1) % 3]), point(in, a[(i + 2) % 3]));
    const Seg opposite_b(point(in, b[(j + 1) % 3]), point(in, b[(j + 2) % 3]));
    return CGAL::do_intersect(triangle(in, s), opposite_b) ||
           CGAL::do_intersect(triangle(in, t), opposite_a);
  }
  return CGAL::do_intersect(triangle(in, s), triangle(in, t));
}

// A point where s and t meet, for the message: the first crossing of an edge of one with the
// other that is not a vertex they share; else the centroid of s.
Vec3 witness(const Input& in, int s, int t) {
  const auto& a = in.triangles[static_cast<size_t>(s)];
  const auto& b = in.triangles[static_cast<size_t>(t)];
  auto shared_vertex = [&](const Point& p) {
    for (int v : a)
      if (point(in, v) == p && std::find(b.begin(), b.end(), v) != b.end()) return true;
    return false;
  };
  for (int side = 0; side < 2; ++side) {
    const auto& e = side ? b : a;
    const Tri other = triangle(in, side ? s : t);
    for (int i = 0; i < 3; ++i) {
      const Seg seg(point(in, e[i]), point(in, e[(i + 1) % 3]));
      if (seg.is_degenerate() || !CGAL::do_intersect(seg, other)) continue;
      const auto x = CGAL::intersection(seg, other);
      if (!x) continue;
      if (const Point* p = boost::get<Point>(&*x)) {
        if (!shared_vertex(*p)) return {p->x(), p->y(), p->z()};
      } else if (const Seg* q = boost::get<Seg>(&*x)) {
        const Point m = CGAL::midpoint(q->source(), q->target());
        return {m.x(), m.y(), m.z()};
      }
    }
  }
  const Point c = CGAL::centroid(triangle(in, s));
  return {c.x(), c.y(), c.z()};
}

std::optional<SelfIntersection> search(const Input& in) {
  const int n = static_cast<int>(in.triangles.size());
  std::vector<Box> boxes;
  boxes.reserve(static_cast<size_t>(n));
  for (int t = 0; t < n; ++t) {
    const auto& v = in.triangles[static_cast<size_t>(t)];
    const Point p = point(in, v[0]), q = point(in, v[1]), r = point(in, v[2]);
    if (CGAL::collinear(p, q, r)) {
      SelfIntersection hit;
      hit.face_a = hit.face_b = face(in, t);
      hit.point = in.vertices[static_cast<size_t>(v[0])];
      return hit;
    }
    boxes.emplace_back(p.bbox() + q.bbox() + r.bbox(), t);
  }
  // Two halves across the median x of the boxes' centres: boxes wholly left of it (L), wholly
  // right (R) and across (S). Every meeting pair lies in L ∪ S, or in R, or in R × S, so two
  // traversals cover them all and run in parallel; each stops at its first intersecting pair
  // and the smaller pair (by faces, then triangles) is reported, so the answer does not
  // depend on the thread count.
  std::vector<double> centres(boxes.size());
  for (size_t k = 0; k < boxes.size(); ++k) centres[k] = boxes[k].min_coord(0) + boxes[k].max_coord(0);
  double split = 0;
  if (!centres.empty()) {
    auto mid = centres.begin() + static_cast<std::ptrdiff_t>(centres.size() / 2);
    std::nth_element(centres.begin(), mid, centres.end());
    split = 0.5 * *mid;
  }
  std::vector<const Box*> left_across, right, across;
  for (const Box& b : boxes) {
    if (b.max_coord(0) < split) {
      left_across.push_back(&b);
    } else if (b.min_coord(0) > split) {
      right.push_back(&b);
    } else {
      left_across.push_back(&b);
      across.push_back(&b);
    }
  }
  std::array<std::pair<int, int>, 2> found{std::pair{-1, -1}, std::pair{-1, -1}};
  // Closed boxes: boxes that only touch are reported, so are faces that only touch.
  const auto run = [&](size_t part) {
    auto callback = [&](const Box* x, const Box* y) {
      const int s = x->info(), t = y->info();
      if (face(in, s) == face(in, t)) return;  // a face's own triangulation is valid
      if (!intersect(in, s, t)) return;
      found[part] = {s, t};
      throw Found{};
    };
    try {
      if (part == 0) {
        CGAL::box_self_intersection_d<CGAL::Sequential_tag>(left_across.begin(), left_across.end(), callback);
      } else {
        CGAL::box_self_intersection_d<CGAL::Sequential_tag>(right.begin(), right.end(), callback);
        CGAL::box_intersection_d<CGAL::Sequential_tag>(right.begin(), right.end(), across.begin(), across.end(),
                                                       callback);
      }
    } catch (const Found&) {
    }
  };
  parallel_for(2, 0, run);
  const auto key = [&](const std::pair<int, int>& p) {
    return std::tuple(std::min(face(in, p.first), face(in, p.second)),
                      std::max(face(in, p.first), face(in, p.second)), std::min(p.first, p.second));
  };
  int first = -1, second = -1;
  for (const auto& p : found)
    if (p.first >= 0 && (first < 0 || key(p) < key({first, second}))) std::tie(first, second) = p;
  if (first < 0) return std::nullopt;
  SelfIntersection hit;
  hit.face_a = std::min(face(in, first), face(in, second));
  hit.face_b = std::max(face(in, first), face(in, second));
  hit.point = witness(in, first, second);
  return hit;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

std::optional<SelfIntersection> find_self_intersection(const Body& body) {
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> face_of;
  triangles.reserve(body.triangles().size());
  face_of.reserve(body.triangles().size());
  for (const Triangle& t : body.triangles()) {
    triangles.push_back(t.v);
    face_of.push_back(t.face);
  }
  const std::vector<Edge>& edges = body.edges();  // sorted by (v0, v1), v0 < v1
  Input in{body.vertices(), triangles, &face_of, [&](int a, int b, int fa, int fb) {
             const Edge key{std::min(a, b), std::max(a, b), 0, 0};
             auto it = std::lower_bound(edges.begin(), edges.end(), key, [](const Edge& x, const Edge& y) {
               return std::tie(x.v0, x.v1) < std::tie(y.v0, y.v1);
             });
             if (it == edges.end() || it->v0 != key.v0 || it->v1 != key.v1) return false;
             return (it->left_face == fa && it->right_face == fb) ||
                    (it->left_face == fb && it->right_face == fa);
           }};
  return search(in);
}

std::optional<SelfIntersection> find_self_intersection(
    const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& triangles) {
  for (const auto& t : triangles)
    for (int v : t)
      if (v < 0 || static_cast<size_t>(v) >= vertices.size())
        throw std::invalid_argument("find_self_intersection: vertex index out of range");
  Input in{vertices, triangles, nullptr, nullptr};
  return search(in);
}

std::string describe(const SelfIntersection& hit) {
  const std::string where =
      " near (" + num(hit.point.x()) + ", " + num(hit.point.y()) + ", " + num(hit.point.z()) + ")";
  if (hit.face_a == hit.face_b)
    return "face " + std::to_string(hit.face_a) + " is degenerate" + where;
  return "faces " + std::to_string(hit.face_a) + " and " + std::to_string(hit.face_b) +
         " intersect" + where;
}

void check_no_self_intersection(const Body& body) {
  if (const auto hit = find_self_intersection(body))
    throw InvalidInput("the surface intersects itself: " + describe(*hit));
}

}  // namespace hedra
