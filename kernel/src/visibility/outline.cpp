#include "hedra/visibility/outline.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace hedra {
namespace {

Vec3 outward_normal(const Body& body, int f) { return -body.inner_normal(f); }

Vec3 face_centre(const Body& body, int f) {
  const auto& loop = body.faces()[static_cast<size_t>(f)].loops[0];
  Vec3 c = Vec3::Zero();
  for (int v : loop) c += body.vertices()[static_cast<size_t>(v)];
  return c / static_cast<double>(loop.size());
}

bool curved(const SmoothSurface& surface, const Vec3& outward) {
  return surface.is_smooth() && surface.curved_face(outward);
}

}  // namespace

std::vector<EdgeClass> classify_edges(const Body& body, double crease_angle_deg,
                                      const SmoothSurface& surface) {
  const double cos_crease = std::cos(crease_angle_deg * std::numbers::pi / 180);
  std::vector<EdgeClass> out;
  out.reserve(body.edges().size());
  for (const Edge& e : body.edges()) {
    const Vec3 a = outward_normal(body, e.left_face), b = outward_normal(body, e.right_face);
    const bool smooth = (curved(surface, a) && curved(surface, b)) || a.dot(b) >= cos_crease;
    out.push_back(smooth ? EdgeClass::Smooth : EdgeClass::Sharp);
  }
  return out;
}

std::vector<Vec3> corner_normals(const Body& body, double crease_angle_deg,
                                 const SmoothSurface& surface) {
  const double cos_crease = std::cos(crease_angle_deg * std::numbers::pi / 180);
  const auto& faces = body.faces();
  const auto& v = body.vertices();
  // Faces around each vertex (CSR).
  std::vector<int> start(v.size() + 1, 0), around;
  for (const Face& face : faces)
    for (const auto& loop : face.loops)
      for (int x : loop) ++start[static_cast<size_t>(x) + 1];
  for (size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  around.resize(static_cast<size_t>(start.back()));
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (size_t f = 0; f < faces.size(); ++f)
      for (const auto& loop : faces[f].loops)
        for (int x : loop) around[static_cast<size_t>(fill[static_cast<size_t>(x)]++)] = static_cast<int>(f);
  }
  std::vector<Vec3> normal(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) normal[f] = outward_normal(body, static_cast<int>(f));

  std::vector<Vec3> out;
  out.reserve(static_cast<size_t>(start.back()));
  for (size_t f = 0; f < faces.size(); ++f) {
    const bool analytic = curved(surface, normal[f]);
    const Vec3 centre = analytic ? face_centre(body, static_cast<int>(f)) : Vec3::Zero();
    for (const auto& loop : faces[f].loops)
      for (int x : loop) {
        if (analytic) {
          out.push_back(surface.normal(v[static_cast<size_t>(x)], centre));
          continue;
        }
        // Area-weighted normals of the faces around x that turn from f by at most the crease
        // angle: a crease keeps its two sides apart, a smooth region shares one normal.
        // A corner where f meets no other face within the crease angle keeps f's normal
        // exactly, so that outline() knows a flat face (a box's) has no contour.
        Vec3 sum = Vec3::Zero();
        bool alone = true;
        for (int i = start[static_cast<size_t>(x)]; i < start[static_cast<size_t>(x) + 1]; ++i) {
          const int g = around[static_cast<size_t>(i)];
          if (normal[static_cast<size_t>(g)].dot(normal[f]) >= cos_crease) {
            sum += body.face_area(g) * normal[static_cast<size_t>(g)];
            alone = alone && static_cast<size_t>(g) == f;
          }
        }
        out.push_back(!alone && sum.norm() > 0 ? Vec3(sum.normalized()) : normal[f]);
      }
  }
  return out;
}

std::vector<OutlineSegment> outline(const Body& body, const Viewpoint& view,
                                    double crease_angle_deg, const SmoothSurface& surface) {
  const std::vector<Vec3> normals = corner_normals(body, crease_angle_deg, surface);
  const auto& faces = body.faces();
  const auto& v = body.vertices();
  // (vertex, corner) pairs of each face, sorted by vertex, to find a triangle's corners.
  std::vector<int> base(faces.size() + 1, 0);
  std::vector<std::pair<int, int>> corner_of;
  for (size_t f = 0; f < faces.size(); ++f) {
    base[f] = static_cast<int>(corner_of.size());
    for (const auto& loop : faces[f].loops)
      for (int x : loop) corner_of.emplace_back(x, static_cast<int>(corner_of.size()));
    std::sort(corner_of.begin() + base[f], corner_of.end());
  }
  base[faces.size()] = static_cast<int>(corner_of.size());
  auto corner = [&](int f, int x) {
    auto first = corner_of.begin() + base[static_cast<size_t>(f)];
    auto last = corner_of.begin() + base[static_cast<size_t>(f) + 1];
    return std::lower_bound(first, last, std::make_pair(x, -1))->second;
  };

  // Singular points of the analytic surface (a cone's apex): the curved faces around the
  // vertex give it different normals, one per face. Every contour generator passes through
  // such a point, so n·r counts as 0 there: the contour reaches it from the one triangle
  // where the sign changes on the opposite side, instead of stopping short at a side.
  std::vector<char> singular(v.size(), 0);
  if (surface.is_smooth()) {
    std::vector<const Vec3*> first(v.size(), nullptr);
    for (size_t f = 0; f < faces.size(); ++f) {
      if (!curved(surface, outward_normal(body, static_cast<int>(f)))) continue;
      for (const auto& loop : faces[f].loops)
        for (int x : loop) {
          const Vec3& n = normals[static_cast<size_t>(corner(static_cast<int>(f), x))];
          const Vec3*& seen = first[static_cast<size_t>(x)];
          if (seen == nullptr) seen = &n;
          else if (!(*seen - n).isZero(1e-9)) singular[static_cast<size_t>(x)] = 1;
        }
    }
  }

  std::vector<OutlineSegment> out;
  for (const Triangle& t : body.triangles()) {
    // A flat-shaded triangle (every corner on the face's own normal) has n·r of one sign in
    // exact arithmetic, the sign facing() decides; rounding must not make a contour there
    // (a box face seen edge-on).
    const Vec3 face_normal = outward_normal(body, t.face);
    bool flat = true;
    for (int k = 0; k < 3; ++k) flat = flat && normals[static_cast<size_t>(corner(t.face, t.v[k]))] == face_normal;
    if (flat) continue;
    double g[3];
    bool positive[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = v[static_cast<size_t>(t.v[k])];
      g[k] = singular[static_cast<size_t>(t.v[k])]
                 ? 0.0
                 : normals[static_cast<size_t>(corner(t.face, t.v[k]))].dot(view.ray_to(p));
      positive[k] = g[k] >= 0;
    }
    if (positive[0] == positive[1] && positive[1] == positive[2]) continue;
    // The two sides whose ends differ in sign; each crossing is interpolated from the end with
    // the smaller vertex index, so that the neighbour across the side gets the same point.
    Vec3 ends[2];
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      int i = k, j = (k + 1) % 3;
      if (positive[i] == positive[j]) continue;
      if (t.v[j] < t.v[i]) std::swap(i, j);
      const Vec3 &pi = v[static_cast<size_t>(t.v[i])], &pj = v[static_cast<size_t>(t.v[j])];
      ends[n++] = pi + (g[i] / (g[i] - g[j])) * (pj - pi);
    }
    out.push_back({ends[0], ends[1], t.face});
  }
  return out;
}

}  // namespace hedra
