#include "hedra/core/primitives.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>
#include <string>

#include "core/primitive_solids.h"
#include "hedra/core/error.h"

namespace hedra {
namespace {

constexpr double kPi = std::numbers::pi;

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

void require(bool ok, const std::string& message) {
  if (!ok) throw InvalidInput(message);
}

void require_finite(double v, const char* what) {
  require(std::isfinite(v), std::string(what) + " is not finite");
}

double signed_area(const Polygon2& p) {
  double a = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec2& u = p[i];
    const Vec2& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - u.y() * v.x();
  }
  return a / 2;
}

// Drops consecutive duplicate and collinear vertices (exact), then orients the polygon
// counter-clockwise (ccw = true) or clockwise.
Polygon2 clean(Polygon2 p, bool ccw, const std::string& what) {
  for (const Vec2& q : p)
    require(q.allFinite(), what + " has a non-finite coordinate");
  bool changed = true;
  while (changed && p.size() >= 3) {
    changed = false;
    for (size_t i = 0; i < p.size() && p.size() >= 3; ++i) {
      const Vec2& a = p[(i + p.size() - 1) % p.size()];
      const Vec2& b = p[i];
      const Vec2& c = p[(i + 1) % p.size()];
      if (a == b || orient2d(a, b, c) == Sign::Zero) {
        // Collinear b: dropped when it lies strictly between a and c (exact coordinate
        // comparisons). Otherwise the outline turns back on itself: a spike of zero width,
        // which makes back-to-back side faces that no later stage can split (fuzz finding:
        // decompose failed with "a piece is not closed").
        const int k = a.x() != c.x() ? 0 : 1;
        const bool between = a == b || (std::min(a[k], c[k]) < b[k] && b[k] < std::max(a[k], c[k]));
        if (!between)
          throw InvalidInput(what + " turns back on itself at (" + number(b.x()) + ", " +
                             number(b.y()) + "): a spike of zero width");
        p.erase(p.begin() + static_cast<long>(i));
        changed = true;
      }
    }
  }
  require(p.size() >= 3, what + " has fewer than 3 non-collinear vertices");
  double area = signed_area(p);
  require(area != 0, what + " has zero area");
  if ((area > 0) != ccw) std::reverse(p.begin(), p.end());
  return p;
}

// True when `p` lies on the closed segment ab (exact: orientation, then the box of ab).
bool on_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  if (orient2d(a, b, p) != Sign::Zero) return false;
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= p.y() && p.y() <= std::max(a.y(), b.y());
}

// The first vertex of `a` on the boundary of `b`, or of `b` on `a`: loops that touch make a
// body pinched along a vertical edge (a T-junction no mesh file can store closed; fuzz finding).
// Cost O(|a|·|b|).
const Vec2* touching_vertex(const Polygon2& a, const Polygon2& b) {
  for (int pass = 0; pass < 2; ++pass) {
    const Polygon2& u = pass ? b : a;
    const Polygon2& v = pass ? a : b;
    for (const Vec2& p : u)
      for (size_t i = 0; i < v.size(); ++i)
        if (on_segment(p, v[i], v[(i + 1) % v.size()])) return &p;
  }
  return nullptr;
}

// Where a loop (cleaned: no repeated or collinear consecutive vertices) is not simple: a vertex
// on an edge that is not its own ("touches"), else a crossing of two edges ("crosses"), with a
// point for the message; nullopt for a simple loop. A loop that touches itself makes a body
// pinched along a vertical edge, as a hole touching the outline does, and one that crosses
// itself side faces through each other (fuzz finding: a prism pinched at a vertex was accepted
// as given and, rotated, rejected as self-intersecting once written and read back). Exact:
// CGAL's sweep (O(n log n)) decides; only a loop that is not simple is searched for the place,
// O(n²).
std::optional<std::pair<const char*, Vec2>> loop_defect(const Polygon2& p) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<K::Point_2> points;
  points.reserve(p.size());
  for (const Vec2& q : p) points.emplace_back(q.x(), q.y());
  if (CGAL::is_simple_2(points.begin(), points.end(), K())) return std::nullopt;
  const size_t n = p.size();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j)
      if (j != i && (j + 1) % n != i && on_segment(p[i], p[j], p[(j + 1) % n])) return std::pair{"touches", p[i]};
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 2; j < n; ++j) {
      if ((j + 1) % n == i) continue;
      const Vec2 &a = p[i], &b = p[(i + 1) % n], &c = p[j], &d = p[(j + 1) % n];
      if (orient2d(a, b, c) != orient2d(a, b, d) && orient2d(c, d, a) != orient2d(c, d, b)) {
        const double t = ((c - a).x() * (d - c).y() - (c - a).y() * (d - c).x()) /
                         ((b - a).x() * (d - c).y() - (b - a).y() * (d - c).x());
        return std::pair{"crosses", Vec2(a + t * (b - a))};
      }
    }
  return std::pair{"crosses", p[0]};  // overlapping collinear edges: the sweep saw them
}

Polygon2 circle(int n, double r) {
  Polygon2 p;
  for (int i = 0; i < n; ++i) {
    double t = 2 * kPi * i / n;
    p.emplace_back(r * std::cos(t), r * std::sin(t));
  }
  return p;
}

}  // namespace

Body box(const Vec3& min, const Vec3& max) {
  require(min.allFinite() && max.allFinite(), "box corners must be finite");
  require((min.array() < max.array()).all(), "box: min must be below max in every coordinate");
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i)
    v.emplace_back(i & 1 ? max.x() : min.x(), i & 2 ? max.y() : min.y(), i & 4 ? max.z() : min.z());
  // Vertex i has x = bit 0, y = bit 1, z = bit 2. Loops counter-clockwise from outside.
  std::vector<Face> faces = {
      {0, 4, 6, 2},  // x = min
      {1, 3, 7, 5},  // x = max
      {0, 1, 5, 4},  // y = min
      {2, 6, 7, 3},  // y = max
      {0, 2, 3, 1},  // z = min
      {4, 5, 7, 6},  // z = max
  };
  return Body(std::move(v), std::move(faces));
}

Body prism(const Polygon2& outline, double z0, double z1, const std::vector<Polygon2>& holes) {
  require_finite(z0, "prism z0");
  require_finite(z1, "prism z1");
  require(z0 < z1, "prism: z0 must be below z1");
  std::vector<Polygon2> loops{clean(outline, true, "prism outline")};
  for (size_t h = 0; h < holes.size(); ++h)
    loops.push_back(clean(holes[h], false, "prism hole " + std::to_string(h)));
  for (size_t h = 0; h < loops.size(); ++h)
    if (const auto defect = loop_defect(loops[h]))
      throw InvalidInput((h == 0 ? std::string("prism outline") : "prism hole " + std::to_string(h - 1)) + " " +
                         defect->first + " itself " + (defect->first[0] == 't' ? "at" : "near") + " (" +
                         number(defect->second.x()) + ", " + number(defect->second.y()) + ")");
  for (size_t h = 1; h < loops.size(); ++h)
    for (size_t g = 0; g < h; ++g)
      if (const Vec2* p = touching_vertex(loops[h], loops[g]))
        throw InvalidInput("prism hole " + std::to_string(h - 1) + " touches " +
                           (g == 0 ? std::string("the outline") : "hole " + std::to_string(g - 1)) +
                           " at (" + number(p->x()) + ", " + number(p->y()) + ")");

  std::vector<Vec3> v;
  std::vector<std::vector<int>> bottom, top;
  std::vector<Face> sides;
  for (const Polygon2& loop : loops) {
    const int base = static_cast<int>(v.size());
    const int k = static_cast<int>(loop.size());
    for (const Vec2& p : loop) v.emplace_back(p.x(), p.y(), z0);
    for (const Vec2& p : loop) v.emplace_back(p.x(), p.y(), z1);
    std::vector<int> b, t;
    for (int i = k - 1; i >= 0; --i) b.push_back(base + i);  // seen from below: reversed
    for (int i = 0; i < k; ++i) t.push_back(base + k + i);
    bottom.push_back(b);
    top.push_back(t);
    for (int i = 0; i < k; ++i) {
      int j = (i + 1) % k;
      sides.push_back(Face{base + i, base + j, base + k + j, base + k + i});
    }
  }
  std::vector<Face> faces{Face(bottom), Face(top)};
  faces.insert(faces.end(), sides.begin(), sides.end());
  return Body(std::move(v), std::move(faces));
}

Body pyramid(const Polygon2& base, double z0, const Vec3& apex) {
  require_finite(z0, "pyramid z0");
  require(apex.allFinite(), "pyramid apex is not finite");
  require(apex.z() != z0, "pyramid apex lies in the plane of its base");
  // Base loop counter-clockwise seen from outside: from below when the apex is above.
  const bool up = apex.z() > z0;
  Polygon2 p = clean(base, up, "pyramid base");
  const int k = static_cast<int>(p.size());
  std::vector<Vec3> v;
  for (const Vec2& q : p) v.emplace_back(q.x(), q.y(), z0);
  v.push_back(apex);
  std::vector<int> b;
  for (int i = k - 1; i >= 0; --i) b.push_back(i);
  std::vector<Face> faces{Face(b)};
  for (int i = 0; i < k; ++i) faces.push_back(Face{i, (i + 1) % k, k});
  return Body(std::move(v), std::move(faces));
}

Body frustum(const Polygon2& base, double z0, const Vec3& apex, double z1) {
  require_finite(z0, "frustum z0");
  require_finite(z1, "frustum z1");
  require(apex.allFinite(), "frustum apex is not finite");
  require((z0 < z1 && z1 < apex.z()) || (z0 > z1 && z1 > apex.z()),
          "frustum: z1 must lie strictly between the base and the apex");
  const bool up = apex.z() > z0;
  Polygon2 p = clean(base, up, "frustum base");
  const int k = static_cast<int>(p.size());
  const double s = (z1 - z0) / (apex.z() - z0);  // fraction of the way to the apex
  std::vector<Vec3> v;
  for (const Vec2& q : p) v.emplace_back(q.x(), q.y(), z0);
  for (const Vec2& q : p)
    v.emplace_back(q.x() + s * (apex.x() - q.x()), q.y() + s * (apex.y() - q.y()), z1);
  std::vector<int> b, t;
  for (int i = k - 1; i >= 0; --i) b.push_back(i);
  for (int i = 0; i < k; ++i) t.push_back(k + i);
  std::vector<Face> faces{Face(b), Face(t)};
  for (int i = 0; i < k; ++i) {
    int j = (i + 1) % k;
    faces.push_back(Face{i, j, k + j, k + i});
  }
  Body body(std::move(v), std::move(faces));
  internal::attach_frustum_solid(body, apex, z0, z1);
  return body;
}

namespace {

void require_budget(const char* shape, double faces, double tolerance, int max_faces) {
  if (faces <= max_faces) return;
  char count[32];
  std::snprintf(count, sizeof count, "%.0f", faces);
  throw FaceBudgetExceeded(std::string(shape) + (tolerance > 0 ? " at chordal tolerance " + number(tolerance) : "") +
                           " needs " + count + " faces, more than the limit of " +
                           std::to_string(max_faces) + " (max_faces)");
}

void require_resolvable(double radius, double tolerance) {
  require(std::isfinite(radius) && radius > 0, "radius must be positive");
  require(std::isfinite(tolerance) && tolerance > 0, "chordal tolerance must be positive");
  if (tolerance < kMinRelativeTolerance * radius)
    throw InvalidInput("chordal tolerance " + number(tolerance) + " is below what doubles can honour at radius " +
                       number(radius) + " (at least " + number(kMinRelativeTolerance) +
                       " of the radius: vertex coordinates are rounded to about 1e-16 of it)");
}

}  // namespace

Body regular_prism(int n, double r, double z0, double z1, int max_faces) {
  require(n >= 3, "a regular prism needs at least 3 sides");
  require(std::isfinite(r) && r > 0, "regular prism radius must be positive");
  require_budget("regular prism", static_cast<double>(n) + 2, 0, max_faces);
  return prism(circle(n, r), z0, z1);
}

int segments_for_tolerance(double radius, double tolerance) {
  require_resolvable(radius, tolerance);
  if (tolerance >= radius) return 3;
  // r (1 − cos(π/n)) <= tol  ⇔  n >= π / acos(1 − tol/r); tol/r >= 1e-13 keeps n below 1e7.
  int n = static_cast<int>(std::ceil(kPi / std::acos(1 - tolerance / radius) - 1e-9));
  while (radius * (1 - std::cos(kPi / n)) > tolerance) ++n;
  return std::max(n, 3);
}

Body cylinder(double radius, double z0, double z1, double tolerance, int max_faces) {
  const int n = segments_for_tolerance(radius, tolerance);
  require_budget("cylinder", static_cast<double>(n) + 2, tolerance, max_faces);
  return regular_prism(n, radius, z0, z1, max_faces);
}

Body cone(double radius, double z0, double z1, double tolerance, int max_faces) {
  const int n = segments_for_tolerance(radius, tolerance);
  require_budget("cone", static_cast<double>(n) + 1, tolerance, max_faces);
  return pyramid(circle(n, radius), z0, Vec3(0, 0, z1));
}

namespace {

// `x` rounded to nearest with `bits` significant bits (exact for |x| below 2^1000).
double with_bits(double x, int bits) {
  if (x == 0) return 0;
  int e = 0;
  std::frexp(x, &e);
  return std::ldexp(std::nearbyint(std::ldexp(x, bits - e)), e - bits);
}

// Vertices and faces of the latitude–longitude sphere with `rings` bands and 2·rings
// meridians, about the origin. Every quadrilateral is exactly planar: ring i's vertices are
// (c_i·C_j, c_i·S_j, z_i) with c_i = r·cos φ_i rounded to 27 significant bits and the
// meridian directions (C_j, S_j) = (cos λ_j, sin λ_j) rounded to 26, so that every product is
// a double exactly; the four corners of a band's face then lie on lines (ρ, z) of one profile
// line through the two meridian directions, a plane, whatever the rounding of c, C and S
// (docs/primitives.md). Each vertex is within kSphereSnap·r (2^-23·r) of the sphere; the
// coordinates keep the sphere's symmetries exactly (mirrored, not computed again).
//
// `grid` > 0: the directions rounded to multiples of 2^-grid and c_i to multiples of
// 2^(E − grid), where r < 2^E ≤ 2r, instead (the grid sphere_grid_bits chooses): every product
// c_i·u_j is then a multiple of 2^(E − 2·grid), which a translation keeps exact.
void sphere_mesh(double r, int rings, bool snapped, std::vector<Vec3>& v, std::vector<Face>& faces,
                 int grid = 0) {
  const int m = 2 * rings;
  const int trig_bits = snapped ? 26 : 53, radial_bits = snapped ? 27 : 53;
  int radius_exponent = 0;
  std::frexp(r, &radius_exponent);
  const auto trig = [&](double x) {
    return grid > 0 ? std::ldexp(std::nearbyint(std::ldexp(x, grid)), -grid) : with_bits(x, trig_bits);
  };
  const auto radial = [&](double x) {
    return grid > 0 ? std::ldexp(std::nearbyint(std::ldexp(x, grid - radius_exponent)), radius_exponent - grid)
                    : with_bits(x, radial_bits);
  };
  std::vector<double> C(static_cast<size_t>(m)), S(static_cast<size_t>(m));
  for (int j = 0; 4 * j <= m; ++j) {  // the first quadrant, then its mirror images
    const double lambda = 2 * kPi * j / m;
    const double c = 4 * j == m ? 0 : trig(std::cos(lambda));
    const double s = j == 0 ? 0 : trig(std::sin(lambda));
    const int mirrored[4] = {j, rings - j, rings + j, m - j};
    const double nc = c == 0 ? 0.0 : -c, ns = s == 0 ? 0.0 : -s;  // no −0
    const double cs[4][2] = {{c, s}, {nc, s}, {nc, ns}, {c, ns}};
    for (int k = 0; k < 4; ++k) {
      const int at = mirrored[k] % m;
      C[static_cast<size_t>(at)] = cs[k][0];
      S[static_cast<size_t>(at)] = cs[k][1];
    }
  }
  std::vector<double> ring_c(static_cast<size_t>(rings)), ring_z(static_cast<size_t>(rings));
  for (int i = 1; 2 * i <= rings; ++i) {  // the southern half, then its mirror image
    const double phi = -kPi / 2 + kPi * i / rings;
    const double c = radial(r * std::cos(phi)), z = 2 * i == rings ? 0 : r * std::sin(phi);
    ring_c[static_cast<size_t>(i)] = ring_c[static_cast<size_t>(rings - i)] = c;
    ring_z[static_cast<size_t>(i)] = z;
    ring_z[static_cast<size_t>(rings - i)] = z == 0 ? 0.0 : -z;
  }
  v.clear();
  faces.clear();
  v.emplace_back(0, 0, -r);
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < m; ++j)
      v.emplace_back(ring_c[static_cast<size_t>(i)] * C[static_cast<size_t>(j)],
                     ring_c[static_cast<size_t>(i)] * S[static_cast<size_t>(j)], ring_z[static_cast<size_t>(i)]);
  v.emplace_back(0, 0, r);
  const int south = 0, north = static_cast<int>(v.size()) - 1;
  auto ring = [&](int i, int j) { return 1 + (i - 1) * m + (j % m); };
  for (int j = 0; j < m; ++j) faces.push_back(Face{south, ring(1, j + 1), ring(1, j)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < m; ++j)
      faces.push_back(Face{ring(i, j), ring(i, j + 1), ring(i + 1, j + 1), ring(i + 1, j)});
  for (int j = 0; j < m; ++j) faces.push_back(Face{north, ring(rings - 1, j), ring(rings - 1, j + 1)});
}

// The grid of sphere_mesh for a sphere about `centre`, so that moving its vertices there is
// exact: 25 bits, each vertex then within r·2^-26·(2 + √2) + 2 ulps of |centre| + r of the
// sphere (< kSphereSnap·r), and every coordinate c_i·u_j a multiple of 2^(E − 50); or 0 where
// the centre's horizontal coordinates are not multiples of the unit U of the moved coordinates
// (the last place of 2·(max |centre| + r)), or U exceeds 2^(E − 50) (a centre further than
// about 4r from the origin). Then x + centre_x is a sum of two multiples of U below 2^53·U:
// a double exactly.
int sphere_grid_bits(const Vec3& centre, double r) {
  constexpr int kGrid = 25;
  int radius_exponent = 0, e = 0;
  std::frexp(r, &radius_exponent);
  std::frexp(2 * (centre.cwiseAbs().maxCoeff() + r), &e);
  const int unit = e - 53;  // U = 2^unit
  if (unit > radius_exponent - 2 * kGrid) return 0;
  for (int k = 0; k < 2; ++k) {
    const double scaled = std::ldexp(centre[k], -unit);
    if (scaled != std::nearbyint(scaled)) return 0;
  }
  return kGrid;
}

}  // namespace

double sphere_chordal_error(double radius, int rings) {
  // All vertices lie on the sphere and each face contains the foot of the perpendicular from
  // the centre (faces are symmetric about their mid-meridian and the foot lies between the
  // face's latitudes), so the largest sphere-to-polyhedron distance is
  // max over faces of r − dist(centre, face plane). Faces of one band are congruent: one
  // face per band is enough. Cost O(rings).
  const int m = 2 * rings;
  auto point = [&](int i, int j) {
    double phi = -kPi / 2 + kPi * i / rings, lambda = 2 * kPi * j / m;
    return Vec3(radius * std::cos(phi) * std::cos(lambda),
                radius * std::cos(phi) * std::sin(lambda), radius * std::sin(phi));
  };
  double worst = 0;
  for (int i = 0; i < rings; ++i) {
    // Band i lies between latitudes i and i + 1; at a pole two of its corners coincide.
    Vec3 a = point(i, 0), b = point(i, 1), c = point(i + 1, 1), d = point(i + 1, 0);
    Vec3 n = i == 0 ? (c - a).cross(d - a) : (b - a).cross(d - a);
    double dist = std::abs(n.normalized().dot(a));
    worst = std::max(worst, radius - dist);
  }
  return worst;
}

Body sphere(const Vec3& centre, double radius, double tolerance, int max_faces) {
  require(centre.allFinite(), "sphere centre is not finite");
  require(std::isfinite(radius) && radius > 0, "sphere radius must be positive");
  require_resolvable(radius, tolerance);
  // Exactly planar faces (sphere_mesh) where the tolerance leaves room for the snap; below
  // 2·kSphereSnap of the radius (a billion faces and more), the vertices on the sphere to the
  // last bit and the quadrilaterals planar within rounding.
  const bool snapped = tolerance >= 2 * kSphereSnap * radius;
  const double snap = snapped ? kSphereSnap * radius : 0;
  // 2·rings² faces: the most rings the budget allows.
  const int max_rings = std::max(2, static_cast<int>(std::sqrt(std::max(max_faces, 8) / 2.0)));
  int rings = 2;
  while (sphere_chordal_error(radius, rings) + snap > tolerance) {
    if (rings >= max_rings) {
      // The error falls as 1/rings²: the rings needed, estimated from the last count tried.
      const double needed = std::max<double>(
          rings + 1, std::ceil(rings * std::sqrt(sphere_chordal_error(radius, rings) / (tolerance - snap))));
      require_budget("sphere", std::max(2 * needed * needed, max_faces + 1.0), tolerance, max_faces);
    }
    ++rings;
  }
  std::vector<Vec3> v;
  std::vector<Face> faces;
  const int grid = snapped && centre != Vec3::Zero() ? sphere_grid_bits(centre, radius) : 0;
  if (grid > 0) {
    // Snapped to a grid the move keeps: the moved corners are the planar sphere moved exactly
    // (checked: a coordinate the move rounded would leave a face planar only within rounding).
    sphere_mesh(radius, rings, snapped, v, faces, grid);
    bool exact = true;
    for (Vec3& p : v) {
      const Vec3 q = p + centre;
      for (int k = 0; k < 2; ++k) {  // Knuth's two-sum: the rounding error of p_k + centre_k
        const double b = q[k] - p[k];
        exact = exact && (p[k] - (q[k] - b)) + (centre[k] - b) == 0;
      }
      p = q;
    }
    if (exact) return Body(std::move(v), std::move(faces));
  }
  sphere_mesh(radius, rings, snapped, v, faces);
  if (centre == Vec3::Zero() || !snapped) {
    for (Vec3& p : v) p += centre;
    return Body(std::move(v), std::move(faces));
  }
  // Moved exactly: the body is the rounding of the translated corners, and keeps the exact
  // image of the planar sphere about the origin (Body::exact_solid()), which Booleans and the
  // exact decompositions of hidden lines and shadows use (as transformed() would, without a
  // second body: a 500 000-face sphere took 2× the time and memory that way).
  std::vector<Vec3> about_origin = v;
  for (Vec3& p : v) p += centre;
  Body body(std::move(v), std::move(faces));
  internal::attach_translated_image(body, std::move(about_origin), centre);
  return body;
}

}  // namespace hedra
