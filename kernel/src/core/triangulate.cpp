#include "hedra/core/triangulate.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cmath>
#include <list>
#include <string>

#include "hedra/core/error.h"
#include "hedra/core/predicates.h"

namespace hedra {
namespace {

// Projection to 2D that keeps counter-clockwise loops (around `normal`) counter-clockwise:
// drop the dominant axis, swapping the remaining two when that axis points negative.
// Dropping a coordinate is exact, so 2D predicates on the result are exact.
struct Projection {
  int u, v;
  Projection(const Vec3& normal) {
    int axis;
    normal.cwiseAbs().maxCoeff(&axis);
    u = (axis + 1) % 3;
    v = (axis + 2) % 3;
    if (normal[axis] < 0) std::swap(u, v);
  }
  Vec2 operator()(const Vec3& p) const { return {p[u], p[v]}; }
};

double area2(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

// A single loop is convex and simple when it never turns right and its vertices, in
// lexicographic order, go up once and down once (which rules out stars like {5/2}).
bool convex_simple(const std::vector<Vec2>& p) {
  const size_t n = p.size();
  int direction_changes = 0;
  bool any_left = false;
  auto less = [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  };
  for (size_t i = 0; i < n; ++i) {
    const Vec2& a = p[i];
    const Vec2& b = p[(i + 1) % n];
    const Vec2& c = p[(i + 2) % n];
    Sign s = orient2d(a, b, c);
    if (s == Sign::Negative) return false;
    if (s == Sign::Positive) any_left = true;
    if (less(a, b) != less(b, c)) ++direction_changes;
  }
  return any_left && direction_changes == 2;
}

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, K>;
using Fb0 = CGAL::Constrained_triangulation_face_base_2<K>;
using Fb = CGAL::Triangulation_face_base_with_info_2<int, K, Fb0>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::No_constraint_intersection_requiring_constructions_tag>;

// Nesting depth of each face: 0 outside, 1 inside the outer loop, 2 inside a hole, ...
void mark_depths(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::list<Cdt::Face_handle> border{cdt.infinite_face()};
  int depth = 0;
  while (!border.empty()) {
    std::list<Cdt::Face_handle> next_border;
    while (!border.empty()) {
      Cdt::Face_handle start = border.front();
      border.pop_front();
      if (start->info() != -1) continue;
      std::list<Cdt::Face_handle> queue{start};
      start->info() = depth;
      while (!queue.empty()) {
        Cdt::Face_handle f = queue.front();
        queue.pop_front();
        for (int i = 0; i < 3; ++i) {
          Cdt::Face_handle n = f->neighbor(i);
          if (n->info() != -1) continue;
          if (cdt.is_constrained({f, i})) {
            next_border.push_back(n);
          } else {
            n->info() = depth;
            queue.push_back(n);
          }
        }
      }
    }
    border.swap(next_border);
    ++depth;
  }
}

}  // namespace

std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<Vec3>& vertices,
                                                    const std::vector<std::vector<int>>& loops,
                                                    const Vec3& normal) {
  const Projection project(normal);
  std::vector<std::array<int, 3>> out;

  // Fast path: one convex loop, fanned from a strictly convex vertex.
  if (loops.size() == 1) {
    const std::vector<int>& loop = loops[0];
    std::vector<Vec2> p;
    p.reserve(loop.size());
    for (int id : loop) p.push_back(project(vertices[id]));
    if (loop.size() == 3) {
      if (orient2d(p[0], p[1], p[2]) != Sign::Positive)
        throw InvalidInput("its vertices are collinear or run clockwise");
      out.push_back({loop[0], loop[1], loop[2]});
      return out;
    }
    if (convex_simple(p)) {
      const size_t n = loop.size();
      size_t apex = 0;  // a strictly convex corner
      while (orient2d(p[(apex + n - 1) % n], p[apex], p[(apex + 1) % n]) != Sign::Positive) ++apex;
      bool flat = false;
      for (size_t k = 1; k + 1 < n && !flat; ++k) {
        size_t i = (apex + k) % n, j = (apex + k + 1) % n;
        if (orient2d(p[apex], p[i], p[j]) == Sign::Positive)
          out.push_back({loop[apex], loop[i], loop[j]});
        else
          flat = true;
      }
      // A flat fan triangle (the apex in line with a straight run of the loop) would leave a
      // loop vertex out of the triangulation, and the body's triangles would not be closed
      // there: the general path keeps every vertex.
      if (!flat) return out;
      out.clear();
    }
  }

  // General path: constrained Delaunay triangulation of all loops.
  Cdt cdt;
  double signed_area = 0;
  // The loops' signed area about one of their vertices (the same sum for any origin): about
  // the coordinate origin, a face 1e6 away lost the 1e-9 agreement below to cancellation and
  // a valid face with a thin hole was rejected.
  const Vec2 origin = project(vertices[loops[0][0]]);
  try {
    for (const std::vector<int>& loop : loops) {
      std::vector<Cdt::Vertex_handle> handles;
      handles.reserve(loop.size());
      for (size_t i = 0; i < loop.size(); ++i) {
        Vec2 q = project(vertices[loop[i]]);
        const size_t before = cdt.number_of_vertices();
        Cdt::Vertex_handle h = cdt.insert(K::Point_2(q.x(), q.y()));
        if (cdt.number_of_vertices() == before)
          throw InvalidInput("its boundary touches itself at vertex " + std::to_string(loop[i]));
        h->info() = loop[i];
        handles.push_back(h);
      }
      for (size_t i = 0; i < loop.size(); ++i) {
        const Vec2 a = project(vertices[loop[i]]) - origin,
                   b = project(vertices[loop[(i + 1) % loop.size()]]) - origin;
        signed_area += 0.5 * (a.x() * b.y() - a.y() * b.x());
        cdt.insert_constraint(handles[i], handles[(i + 1) % loop.size()]);
      }
    }
  } catch (const Cdt::Intersection_of_constraints_exception&) {
    throw InvalidInput("its boundary crosses itself");
  }
  mark_depths(cdt);

  double area = 0, abs_sum = 0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (f->info() % 2 != 1) continue;
    const int a = f->vertex(0)->info(), b = f->vertex(1)->info(), c = f->vertex(2)->info();
    double t = area2(project(vertices[a]), project(vertices[b]), project(vertices[c])) / 2;
    if (orient2d(project(vertices[a]), project(vertices[b]), project(vertices[c])) ==
        Sign::Positive) {
      out.push_back({a, b, c});
    }
    area += t;
    abs_sum += std::abs(t);
    if (f->info() > 2) throw InvalidInput("its loops are nested more than one level deep");
  }
  // The triangles inside must cover exactly the area the loops enclose; they do not when a
  // hole lies outside the outer loop, loops overlap, or loops run the wrong way.
  const double scale = std::max(abs_sum, std::abs(signed_area));
  if (out.empty() || std::abs(area - signed_area) > 1e-9 * scale)
    throw InvalidInput("its loops do not bound a region (a hole outside the outer loop, "
                       "overlapping loops, or a loop running the wrong way)");
  return out;
}

}  // namespace hedra
