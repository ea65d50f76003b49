// Open surfaces (hedra/mesh/open_surface.h): two-sided faces that occlude, receive and cast
// shadows and render, checked against independent references: ray casting of edge samples
// (hidden lines), CGAL's exact union of the triangles projected along the light (shadows), the
// projected area in pixels (rendering).
#include "hedra/mesh/open_surface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>

#include "hedra/core/error.h"
#include "hedra/core/primitives.h"
#include "hedra/core/transform.h"
#include "hedra/render/raster.h"
#include "hedra/visibility/polygon_set.h"
#include "hedra/visibility/roberts.h"
#include "hedra/visibility/shadows.h"

namespace hedra {
namespace {

constexpr double kPi = std::numbers::pi;

// An open surface in both forms the kernel takes: a two-sided body per convex face
// (two_sided_faces, as the API gives them) and one two-sided body of them all
// (two_sided_surface, as scene and mesh files give them). Every drawing and shadow below must
// come out the same from either.
std::vector<std::pair<const char*, std::vector<Body>>> both_forms(const PolygonSoup& soup) {
  return {{"a body per face", two_sided_faces(soup)}, {"one surface body", {two_sided_surface(soup)}}};
}

// ---- Two-sided faces ----

TEST(TwoSidedPolygon, IsAFlatBodyOfTwoOppositeFaces) {
  const Body f = Body::two_sided_polygon({{0, 0, 1}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1}});
  EXPECT_TRUE(f.two_sided());
  EXPECT_EQ(f.face_count(), 2);
  EXPECT_EQ(f.edge_count(), 4);
  EXPECT_DOUBLE_EQ(f.face_area(0), 4);
  EXPECT_DOUBLE_EQ(f.face_area(1), 4);
  EXPECT_EQ(f.volume(), 0);
  // Face 0 runs counter-clockwise seen from +z: its inner normal points down.
  EXPECT_NEAR(f.inner_normal(0).z(), -1, 1e-15);
  EXPECT_NEAR(f.inner_normal(1).z(), 1, 1e-15);
  // From either side exactly one face is Front.
  for (const Vec3& d : {Vec3(0.1, 0.2, -1), Vec3(0.3, -0.1, 1)}) {
    const Viewpoint v = Viewpoint::towards(d);
    EXPECT_NE(facing(f, 0, v) == Facing::Front, facing(f, 1, v) == Facing::Front);
  }
  EXPECT_FALSE(box({0, 0, 0}, {1, 1, 1}).two_sided());
  // Moved, it stays two-sided (a reflection keeps face 0 the given polygon's way round).
  const Body m = f.rotated_x(30).scaled({-1, 1, 1});
  EXPECT_TRUE(m.two_sided());
  EXPECT_NEAR(m.face_area(0), 4, 1e-12);
}

TEST(TwoSidedPolygon, RejectsNonConvexNonPlanarAndDegeneratePolygons) {
  EXPECT_THROW(Body::two_sided_polygon({{0, 0, 0}, {1, 0, 0}}), InvalidInput);
  EXPECT_THROW(Body::two_sided_polygon({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}), InvalidInput);
  EXPECT_THROW(Body::two_sided_polygon({{0, 0, 0}, {2, 0, 0}, {1, 0.5, 0}, {2, 2, 0}, {0, 2, 0}}),
               InvalidInput);  // reflex corner
  EXPECT_THROW(Body::two_sided_polygon({{0, 0, 0}, {1, 0, 0}, {1, 1, 1e-9}, {0, 1, 0}}),
               InvalidInput);  // not planar
  EXPECT_THROW(Body::two_sided_polygon({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}}),
               InvalidInput);  // collinear corner
  // A pentagram turns the same way at every corner but winds twice: not convex.
  std::vector<Vec3> star;
  for (int k = 0; k < 5; ++k) star.emplace_back(std::cos(4 * kPi * k / 5), std::sin(4 * kPi * k / 5), 0.5);
  EXPECT_THROW(Body::two_sided_polygon(star), InvalidInput);
  std::vector<Vec3> pentagon;
  for (int k = 0; k < 5; ++k) pentagon.emplace_back(std::cos(2 * kPi * k / 5), std::sin(2 * kPi * k / 5), 0.5);
  EXPECT_NO_THROW(Body::two_sided_polygon(pentagon));
}

// A rotation rounds the corners off their exact plane: the face stays a two-sided face
// (planar within rounding, as a rotated body's faces).
TEST(TwoSidedPolygon, SurvivesAGenericRotation) {
  const Body square = Body::two_sided_polygon({{0, 0, 1}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1}});
  const Body turned = square.transformed(Transform::rotation(Vec3(0.3, -0.7, 0.65), 37.3, Vec3(1, 1, 0)));
  EXPECT_TRUE(turned.two_sided());
  EXPECT_NEAR(turned.face_area(0), 4, 1e-12);
  // Not planar beyond rounding: still refused.
  EXPECT_THROW(Body::two_sided_polygon({{0, 0, 0}, {1, 0, 0}, {1, 1, 1e-9}, {0, 1, 0}}, 1e-10), InvalidInput);
  EXPECT_NO_THROW(Body::two_sided_polygon({{0, 0, 0}, {1, 0, 0}, {1, 1, 1e-9}, {0, 1, 0}}, 1e-8));
}

// One two-sided body of a surface: both sides of every face, each shared edge on both sides,
// each boundary edge joining a face to its other side; by hand for two squares meeting at a
// right angle (an L-shaped sheet) and a flat square beside them.
TEST(TwoSidedSurface, IsOneFlatBodyOfBothSidesOfEveryFace) {
  const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, 1}, {1, 1, 1},
                               {2, 0, 0}, {2, 1, 0}, {9, 9, 9}};  // the last unused
  const Body s = Body::two_sided_surface(v, {{0, 1, 2, 3}, {1, 4, 5, 2}});
  EXPECT_TRUE(s.two_sided());
  EXPECT_EQ(s.vertex_count(), 6) << "only used vertices";
  EXPECT_EQ(s.face_count(), 4);
  // 7 edges: 1 shared (on both sides: 2 copies) and 6 boundary.
  EXPECT_EQ(s.edge_count(), 8);
  int shared = 0, boundary = 0;
  for (const Edge& e : s.edges()) {
    if (e.left_face == s.twin_face(e.right_face)) {
      ++boundary;
    } else {
      ++shared;
      EXPECT_EQ(e.left_face < 2, e.right_face < 2) << "a shared edge stays on one side";
    }
  }
  EXPECT_EQ(shared, 2);
  EXPECT_EQ(boundary, 6);
  EXPECT_EQ(s.twin_face(0), 2);
  EXPECT_EQ(s.twin_face(3), 1);
  EXPECT_DOUBLE_EQ(s.area(), 4);
  EXPECT_EQ(s.volume(), 0);
  EXPECT_NEAR(s.inner_normal(0).z(), -1, 1e-15);
  EXPECT_NEAR(s.inner_normal(2).z(), 1, 1e-15);
  EXPECT_EQ(s.classify({0.5, 0.5, 0}), Location::OnBoundary);
  EXPECT_EQ(s.classify({0.5, 0.5, 0.5}), Location::Outside);
  EXPECT_EQ(s.triangles().size(), 8u);
  for (size_t t = 0; t < 4; ++t) EXPECT_LT(s.triangles()[t].face, 2) << "front side's triangles first";
  // From either side of each face exactly one of it and its twin is Front.
  const Viewpoint view = Viewpoint::towards(Vec3(0.3, 0.2, -1));
  for (int f = 0; f < 2; ++f)
    EXPECT_NE(facing(s, f, view) == Facing::Front, facing(s, s.twin_face(f), view) == Facing::Front);
  // Moved (a reflection keeps each face its given way round), it stays one surface.
  const Body m = s.rotated_x(30).scaled({-1, 1, 1});
  EXPECT_TRUE(m.two_sided());
  EXPECT_EQ(m.face_count(), 4);
  EXPECT_NEAR(m.area(), 4, 1e-12);
  // Refused: a non-convex face, an edge used twice one way, a vertex out of range.
  EXPECT_THROW(Body::two_sided_surface(v, {{0, 1, 2, 3}, {6, 7, 2, 1, 4}}), InvalidInput);
  EXPECT_THROW(Body::two_sided_surface(v, {{0, 1, 2, 3}, {1, 2, 7, 6}}), InvalidInput);
  EXPECT_THROW(Body::two_sided_surface(v, {{0, 1, 12}}), InvalidInput);
  // From a soup: vertices of equal coordinates are one, exactly coplanar neighbours one face.
  PolygonSoup soup;
  soup.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, 0}, {2, 0, 1}};
  soup.polygons = {{0, 1, 2}, {0, 3, 4}, {5, 6, 2}};
  const Body joined = two_sided_surface(soup);
  EXPECT_EQ(joined.face_count(), 4) << "the two flat triangles are one square";
  EXPECT_EQ(joined.vertex_count(), 5);
}

// A flat grid of n × n cells of two triangles over [0, 5]² on the tilted plane
// z = 0.3x + 0.2y, every vertex moved off it along z by up to `noise` (a fixed sequence).
PolygonSoup noisy_grid(int n, double noise) {
  PolygonSoup soup;
  unsigned state = 12345;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      state = state * 1103515245u + 12345u;
      const double r = static_cast<double>((state >> 8) % 2001) / 1000 - 1;  // [-1, 1]
      const double x = 5.0 * i / n, y = 5.0 * j / n;
      soup.vertices.push_back({x, y, 0.3 * x + 0.2 * y + noise * r});
    }
  const auto at = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      soup.polygons.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      soup.polygons.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return soup;
}

TEST(TwoSidedFaces, ToleranceMergesANoisyFlatGridIntoOneFace) {
  const PolygonSoup grid = noisy_grid(10, 1e-9);
  // Exact (D = 0), or D below the noise: the triangles are not coplanar and stay apart.
  EXPECT_GT(two_sided_faces(grid).size(), 150u);
  EXPECT_GT(two_sided_faces(grid, 1e-12).size(), 150u);
  // D = 1e-6: one face, the grid's four corners moved by at most D.
  const std::vector<Body> merged = two_sided_faces(grid, 1e-6);
  ASSERT_EQ(merged.size(), 1u);
  const Body& face = merged[0];
  ASSERT_EQ(face.vertex_count(), 4);
  for (const Vec3& p : face.vertices()) {
    double nearest = 1e300;
    for (int corner : {0, 10, 120, 110}) nearest = std::min(nearest, (p - grid.vertices[corner]).norm());
    EXPECT_LE(nearest, 1e-6) << p.transpose();
  }
  // Certified: every input vertex within D of the face's plane (and inside it: the corners
  // bound the grid), the area that of the plane's square within the noise.
  const Plane& plane = face.plane(0);
  for (const Vec3& p : grid.vertices) EXPECT_LE(std::abs(plane.value(p)), 1e-6);
  EXPECT_NEAR(face.face_area(0), 25 * std::sqrt(1 + 0.09 + 0.04), 1e-6);
  // A surface that is not flat keeps its crease: a roof of two noisy grids (the second one the
  // first mirrored in x = 5, without noise).
  PolygonSoup roof = noisy_grid(4, 1e-9);
  const int base = static_cast<int>(roof.vertices.size());
  for (int j = 0; j <= 4; ++j)
    for (int i = 1; i <= 4; ++i) {
      const double x = 5 + 5.0 * i / 4, y = 5.0 * j / 4;
      roof.vertices.push_back({x, y, 0.3 * (10 - x) + 0.2 * y});
    }
  const auto at = [&](int i, int j) { return i == 0 ? j * 5 + 4 : base + j * 4 + (i - 1); };
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      roof.polygons.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      roof.polygons.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  // Its two sides, each one quadrilateral: the ridge's inner vertices (shared by the two
  // regions, within D of the ridge) left out of both, so the two faces still meet edge to edge.
  const std::vector<Body> sides = two_sided_faces(roof, 1e-6);
  ASSERT_EQ(sides.size(), 2u);
  double area = 0;
  for (const Body& f : sides) {
    EXPECT_EQ(f.vertex_count(), 4);
    area += f.face_area(0);
  }
  int shared = 0;
  for (const Vec3& p : sides[0].vertices())
    for (const Vec3& q : sides[1].vertices()) shared += p == q;
  EXPECT_EQ(shared, 2);
  EXPECT_NEAR(area, 2 * 25 * std::sqrt(1 + 0.09 + 0.04), 1e-6);
}

TEST(TwoSidedFaces, KeepsConvexPolygonsMergesCoplanarTrianglesSplitsTheRest) {
  PolygonSoup soup;
  soup.vertices = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {1, 1, 1}, {3, 1, 0.5}};
  // A flat square given as two triangles, and a non-planar quad hanging off its edge 1–2.
  soup.polygons = {{0, 1, 2}, {0, 2, 3}, {1, 5, 4, 2}};
  const std::vector<Body> faces = two_sided_faces(soup);
  double area = 0;
  int squares = 0;
  for (const Body& f : faces) {
    area += f.face_area(0);
    squares += f.vertex_count() == 4 && std::abs(f.face_area(0) - 4) < 1e-15;
  }
  EXPECT_EQ(squares, 1);  // the two coplanar triangles merged back into the square
  EXPECT_EQ(faces.size(), 3u);  // the non-planar quad as its two triangles
  const auto tri = [&](int a, int b, int c) {
    return 0.5 * (soup.vertices[b] - soup.vertices[a]).cross(soup.vertices[c] - soup.vertices[a]).norm();
  };
  const double quad = std::min(tri(1, 5, 4) + tri(1, 4, 2), tri(1, 5, 2) + tri(5, 4, 2));
  const double other = std::max(tri(1, 5, 4) + tri(1, 4, 2), tri(1, 5, 2) + tri(5, 4, 2));
  EXPECT_TRUE(std::abs(area - 4 - quad) < 1e-12 || std::abs(area - 4 - other) < 1e-12) << area;
  const SurfaceBoundary boundary = surface_boundary(soup);
  EXPECT_EQ(boundary.edges, 8);
  EXPECT_EQ(boundary.boundary_edges, 6);
}

// ---- Hidden lines: a box partly behind a single square face ----

// Brute-force reference: is the ray from x towards the viewer blocked by the open square or
// the open interior of the box? Double arithmetic, for scenes in general position.
struct BoxAndSquare {
  Eigen::AlignedBox3d box;
  std::array<Vec3, 4> square;
  Vec3 towards_viewer;  // unit, parallel view
  std::optional<Vec3> eye;  // perspective view: rays end at the eye (t < 1)

  bool blocked(const Vec3& x) const {
    const Vec3 d = eye ? Vec3(*eye - x) : towards_viewer;
    const double end = eye ? 1.0 : INFINITY;
    // Square: the ray crosses its plane at a point strictly inside it.
    const Vec3 n = (square[1] - square[0]).cross(square[2] - square[0]);
    const double denom = n.dot(d);
    if (std::abs(denom) > 1e-14) {
      const double t = n.dot(square[0] - x) / denom;
      if (t > 1e-12 && t < end) {
        const Vec3 q = x + t * d;
        bool inside = true;
        for (int k = 0; k < 4; ++k)
          inside = inside && (square[(k + 1) % 4] - square[k]).cross(q - square[k]).dot(n) > 1e-12;
        if (inside) return true;
      }
    }
    // Box: the ray's parameter interval inside the open box is not empty and lies ahead.
    double lo = 1e-12, hi = end;
    for (int i = 0; i < 3; ++i) {
      if (std::abs(d[i]) < 1e-300) {
        if (!(x[i] > box.min()[i] && x[i] < box.max()[i])) return false;
        continue;
      }
      double a = (box.min()[i] - x[i]) / d[i], b = (box.max()[i] - x[i]) / d[i];
      if (a > b) std::swap(a, b);
      lo = std::max(lo, a), hi = std::min(hi, b);
    }
    return hi - lo > 1e-9;
  }

  // Visible length of segment p q: 2000 samples at cell centres, transitions bisected.
  double visible_length(const Vec3& p, const Vec3& q) const {
    const int n = 2000;
    const auto at = [&](double t) { return Vec3(p + t * (q - p)); };
    double visible = 0, from = 0;
    bool state = blocked(at(0.5 / n));
    for (int k = 1; k < n; ++k) {
      const double prev = (k - 0.5) / n, t = (k + 0.5) / n;
      if (blocked(at(t)) == state) continue;
      double lo = prev, hi = t;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (blocked(at(mid)) == state ? lo : hi) = mid;
      }
      if (!state) visible += lo - from;
      from = lo;
      state = !state;
    }
    if (!state) visible += 1 - from;
    return visible * (q - p).norm();
  }
};

TEST(OpenSurfaceHiddenLines, BoxPartlyBehindASquareMatchesRayCasting) {
  // Three parallel views, and the same three in perspective from eyes 6 units back.
  for (int view = 0; view < 6; ++view) {
    const Vec3 dirs[] = {Vec3(-1, -2, -1.5), Vec3(0.3, -1.7, -0.8), Vec3(-0.6, -1.1, 0.45)};
    const Vec3 dir = dirs[view % 3];
    const bool perspective = view >= 3;
    BoxAndSquare ref;
    ref.box = Eigen::AlignedBox3d(Vec3(0, 0, 0), Vec3(1, 1, 1));
    // A tilted square between the viewer and the box, covering part of it.
    const Vec3 c = Vec3(0.7, 0.55, 0.6) - 0.9 * dir.normalized();
    const Vec3 u = dir.cross(Vec3(0.2, 0.3, 1)).normalized() * 0.45;
    const Vec3 w = dir.normalized().cross(u).normalized() * 0.45 + 0.1 * dir.normalized();
    ref.square = {c - u - w, c + u - w, c + u + w, c - u + w};
    ref.towards_viewer = -dir.normalized();
    const Vec3 eye = Vec3(0.5, 0.5, 0.5) - 6 * dir.normalized();
    if (perspective) ref.eye = eye;
    // Rounded corners may not be exactly coplanar: the square is given as two triangles.
    PolygonSoup soup;
    soup.vertices = {ref.square[0], ref.square[1], ref.square[2], ref.square[3]};
    soup.polygons = {{0, 1, 2}, {0, 2, 3}};
    Scene scene;
    const Body cube = box({0, 0, 0}, {1, 1, 1});
    scene.add("box", cube);
    const std::vector<Body> faces = two_sided_faces(soup);
    for (size_t i = 0; i < faces.size(); ++i) scene.add("square" + std::to_string(i), faces[i]);
    scene.camera = perspective ? Camera::perspective(eye, Vec3(0.5, 0.5, 0.5), 60) : Camera::parallel(dir);
    HlrOptions options;
    options.junctions = false;
    const HlrResult result = hidden_lines(scene, options);
    // Every box edge: hedra's visible length against the reference's.
    double hidden_by_square = 0;
    for (int e = 0; e < cube.edge_count(); ++e) {
      const Edge& edge = cube.edges()[static_cast<size_t>(e)];
      const Vec3 &p = cube.vertices()[edge.v0], &q = cube.vertices()[edge.v1];
      double got = 0;
      for (const HlrSegment& s : result.visible)
        if (s.body == 0 && s.edge == e) got += (s.b - s.a).norm();
      const double want = ref.visible_length(p, q);
      EXPECT_NEAR(got, want, 1e-9) << "edge " << e << " view " << view;
      BoxAndSquare alone = ref;
      alone.square = {Vec3(99, 99, 99), Vec3(99, 99, 99), Vec3(99, 99, 99), Vec3(99, 99, 99)};
      hidden_by_square += alone.visible_length(p, q) - want;
    }
    EXPECT_GT(hidden_by_square, 0.1) << "the square hides part of the box, view " << view;
    // The square's own edges: in front of the box, so wholly visible (two triangles merged
    // into one face when coplanar; a rounded diagonal is visible too).
    double square_visible = 0, square_edges = 0;
    for (const HlrSegment& s : result.visible)
      if (s.body >= 1) square_visible += (s.b - s.a).norm();
    for (int k = 0; k < 4; ++k) square_edges += (ref.square[(k + 1) % 4] - ref.square[k]).norm();
    if (faces.size() == 1) EXPECT_NEAR(square_visible, square_edges, 1e-12);
    else EXPECT_GE(square_visible, square_edges - 1e-12);
  }
}

// ---- Hidden lines: line classes and outlines of open surfaces ----

// A unit hemispherical bowl (z ≤ 0, open at the rim z = 0) of `m` longitudes and `rings`
// latitude bands, as triangles wound outward (away from the centre).
PolygonSoup bowl(int m, int rings) {
  PolygonSoup soup;
  soup.vertices.push_back({0, 0, -1});  // the pole
  for (int r = 1; r <= rings; ++r) {
    const double lat = -kPi / 2 + kPi / 2 * r / rings;
    for (int k = 0; k < m; ++k) {
      const double lon = 2 * kPi * k / m;
      soup.vertices.push_back({std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), r == rings ? 0.0 : std::sin(lat)});
    }
  }
  const auto at = [&](int r, int k) { return 1 + (r - 1) * m + (k % m); };
  for (int k = 0; k < m; ++k) soup.polygons.push_back({0, at(1, k + 1), at(1, k)});
  for (int r = 1; r < rings; ++r)
    for (int k = 0; k < m; ++k) {
      soup.polygons.push_back({at(r, k), at(r, k + 1), at(r + 1, k + 1)});
      soup.polygons.push_back({at(r, k), at(r + 1, k + 1), at(r + 1, k)});
    }
  return soup;
}

TEST(OpenSurfaceHiddenLines, BowlIsDrawnAsItsRimAndItsOutline) {
  // Seen in parallel along d = (1, 0, −1): the rim (z = 0) is wholly visible (every ray to it
  // comes from above the bowl), and the outline is the contour n·d = 0 of the sphere, the
  // half great circle x = z ≤ 0 in the plane normal to d: a half circle of radius 1 in the
  // picture, π long, hidden by nothing (a tangent ray meets the sphere only at its point).
  // By hand: the rim's projected chords, and π within the chordal error. No other mesh edge is
  // drawn: with the default crease angle of 30° every edge between two faces is smooth.
  const int m = 128, rings = 32;
  const PolygonSoup soup = bowl(m, rings);
  for (const auto& [form, faces] : both_forms(soup)) {
  SCOPED_TRACE(form);
  const Vec3 d(1, 0, -1);
  const Camera camera = Camera::parallel(d);
  double rim = 0;
  const Vec3 u = d.normalized();
  for (int k = 0; k < m; ++k) {
    const Vec3 chord = soup.vertices[1 + (rings - 1) * m + (k + 1) % m] - soup.vertices[1 + (rings - 1) * m + k];
    rim += (chord - chord.dot(u) * u).norm();
  }
  HlrOptions options;
  options.junctions = false;
  const HlrResult r = hidden_lines(faces, camera, options);
  EXPECT_NEAR(r.picture_length(LineKind::Edge), rim, 1e-9);
  for (const HlrSegment& s : r.visible)
    if (s.kind == LineKind::Edge) {
      EXPECT_TRUE(s.a.z() == 0 && s.b.z() == 0) << "a drawn edge off the rim";
    }
  // At the rim the corner normals are one-sided (the faces below only): tilted down by about
  // half a band's angle, they move the contour's ends along the rim by O(band), so the whole
  // outline is π within 2 %; away from the rim (z ≤ −0.1) the error is the chordal one: there
  // the outline is the arc θ ∈ [asin(0.1·√2), π − asin(0.1·√2)] of the half circle
  // p(θ) = (−sin θ/√2, cos θ, −sin θ/√2), within 0.5 %, and on the plane x = z.
  EXPECT_NEAR(r.picture_length(LineKind::Outline), kPi, 2e-2 * kPi);
  const double arc = kPi - 2 * std::asin(0.1 * std::sqrt(2.0));
  double deep = 0;
  for (const HlrSegment& s : r.visible) {
    if (s.kind != LineKind::Outline) continue;
    // The part with z ≤ −0.1 (z is linear along the segment).
    double t0 = 0, t1 = 1;
    const double za = s.a.z() + 0.1, zb = s.b.z() + 0.1;
    if (za > 0 && zb > 0) continue;
    if (za > 0) t0 = za / (za - zb);
    if (zb > 0) t1 = za / (za - zb);
    deep += (t1 - t0) * (s.b2 - s.a2).norm();
    for (const Vec3& p : {s.a, s.b}) {
      if (p.z() <= -0.1) {
        EXPECT_LT(std::abs(p.x() - p.z()), 2e-3) << p.transpose();
      }
    }
  }
  EXPECT_NEAR(deep, arc, 5e-3 * arc);
  EXPECT_EQ(r.stats.smooth_edges, (3 * m * (2 * rings - 1) - m) / 2) << "every edge but the rim's";
  // From a finite eye e = −6·d/|d| (perspective, looking at the centre): the contour of the
  // sphere is where the ray from the eye is tangent, the plane e·p = 1; the rim is again
  // wholly visible (every ray to it comes from above), 2m·sin(π/m) long in space. The
  // interpolated contour lies within 2e-3 of that plane (measured; the facets lie inside the
  // sphere by the chordal error), checked at twice that.
  {
    const Vec3 eye = -6 * u;
    HlrOptions persp = options;
    const HlrResult pr = hidden_lines(faces, Camera::perspective(eye, Vec3::Zero(), 40), persp);
    EXPECT_NEAR(pr.length(LineKind::Edge), 2 * m * std::sin(kPi / m), 1e-9);
    int points = 0;
    for (const HlrSegment& s : pr.visible)
      if (s.kind == LineKind::Outline)
        for (const Vec3& p : {s.a, s.b})
          if (p.z() <= -0.1) {
            ++points;
            EXPECT_LT(std::abs(eye.dot(p) - 1), 4e-3) << p.transpose();
          }
    EXPECT_GT(points, 50);
  }
  // Without line classes (crease angle 0) every facet edge is drawn and there is no outline.
  options.crease_angle = 0;
  const HlrResult all = hidden_lines(faces, camera, options);
  EXPECT_EQ(all.picture_length(LineKind::Outline), 0);
  EXPECT_GT(all.picture_length(LineKind::Edge), 10 * rim);
  // At the largest crease angle every edge between faces is smooth, but the rim stays sharp
  // (a boundary edge joins a face to its other side: 180°, which rounding must not decide).
  options.crease_angle = 180;
  const HlrResult flat = hidden_lines(faces, camera, options);
  EXPECT_NEAR(flat.picture_length(LineKind::Edge), rim, 1e-9);
  }
}

TEST(OpenSurfaceHiddenLines, RotatedTroughKeepsItsBoundaryAndValleyAsSharpEdges) {
  // A V trough z = |x| over [−1, 1] × [0, 2], two 45° slopes given as 8 × 8 grids of
  // triangles, under a generic rotation: rounding leaves the triangles of a slope nearly but
  // not exactly coplanar (so they stay separate faces), and their shared edges are smooth; the
  // valley (the slopes turn by 90°) and the boundary are sharp. Seen from above, everything is
  // visible; by hand, in the picture plane (the rotated xy plane): the boundary 2 + 2 + 2 + 2
  // and the valley 2.
  const Transform rot = Transform::rotation({0.3, 0.7, 0.2}, 33);
  PolygonSoup soup;
  const int n = 8;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= 2 * n; ++i) {
      const double x = -1 + 1.0 * i / n, y = 2.0 * j / n;
      soup.vertices.push_back(rot.apply(Vec3(x, y, std::abs(x))));
    }
  const auto at = [&](int i, int j) { return j * (2 * n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < 2 * n; ++i) {
      soup.polygons.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      soup.polygons.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  ASSERT_GT(two_sided_faces(soup).size(), 20u) << "rounding should keep most triangles apart";
  for (const auto& [form, faces] : both_forms(soup)) {
  SCOPED_TRACE(form);
  const Camera camera = Camera::parallel(rot.apply_vector({0.1, 0.2, -1}), rot.apply_vector({0, 1, 0}));
  HlrOptions options;
  options.junctions = false;
  options.smooth = true;
  const HlrResult r = hidden_lines(faces, camera, options);
  // Picture lengths along the slanted view: each segment's projection onto the plane normal
  // to the view, computed here from the world segments.
  const Vec3 v = rot.apply_vector({0.1, 0.2, -1}).normalized();
  double edges = 0, want = 0;
  for (const HlrSegment& s : r.visible)
    if (s.kind == LineKind::Edge) {
      const Vec3 e = s.b - s.a;
      edges += (e - e.dot(v) * v).norm();
    }
  const auto projected = [&](const Vec3& a, const Vec3& b) {
    const Vec3 e = rot.apply_vector(b - a);
    return (e - e.dot(v) * v).norm();
  };
  // Boundary: y = 0 and y = 2 (two slopes each), x = ±1; the valley x = 0.
  for (const double y : {0.0, 2.0})
    want += projected({-1, y, 1}, {0, y, 0}) + projected({0, y, 0}, {1, y, 1});
  want += 2 * projected({1, 0, 1}, {1, 2, 1}) + projected({0, 0, 0}, {0, 2, 0});
  EXPECT_NEAR(edges, want, 1e-9);
  EXPECT_EQ(r.picture_length(LineKind::Outline), 0) << "seen from above, no contour";
  // Each smooth edge once (two faces share it), none on the valley.
  std::vector<std::array<double, 6>> smooth;
  for (const HlrSegment& s : r.visible)
    if (s.kind == LineKind::Smooth) {
      Vec3 a = s.a, b = s.b;
      if (std::lexicographical_compare(b.data(), b.data() + 3, a.data(), a.data() + 3)) std::swap(a, b);
      smooth.push_back({a.x(), a.y(), a.z(), b.x(), b.y(), b.z()});
      const Vec3 local = rot.inverse().apply(Vec3(0.5 * (s.a + s.b)));
      EXPECT_GT(std::abs(local.x()), 1e-6) << "a valley edge drawn as smooth";
    }
  EXPECT_GT(smooth.size(), 100u);
  std::sort(smooth.begin(), smooth.end());
  EXPECT_EQ(std::adjacent_find(smooth.begin(), smooth.end()), smooth.end()) << "a smooth edge drawn twice";
  }
}

TEST(OpenSurfaceHiddenLines, CrossingSurfacesMeetInAJunctionNeighboursDoNot) {
  // Two single-face surfaces crossing: the square [−1, 1]² at z = 0 and the square x = 0,
  // y ∈ [−0.5, 0.5], z ∈ [−1, 1]. Their junction is the segment x = z = 0, |y| ≤ 0.5, seen
  // whole from above (it lies on both faces, which do not hide it): length 1, by hand.
  const Camera camera = Camera::parallel({0.3, 0.2, -1});
  HlrOptions options;
  std::vector<Body> faces = {
      Body::two_sided_polygon({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}),
      Body::two_sided_polygon({{0, -0.5, -1}, {0, 0.5, -1}, {0, 0.5, 1}, {0, -0.5, 1}})};
  const HlrResult crossing = hidden_lines(faces, camera, options);
  EXPECT_NEAR(crossing.length(LineKind::Junction), 1, 1e-12);
  // A surface whose faces meet only at shared edges and corners (a fan of 12 triangles round
  // an apex, a shallow cone, and a flat square beside it sharing one edge): no junction line,
  // however many of its faces' boxes meet; its boundary drawn whole.
  PolygonSoup fan;
  fan.vertices.push_back({0, 0, 0.3});
  for (int k = 0; k < 12; ++k)
    fan.vertices.push_back({std::cos(2 * kPi * k / 12), std::sin(2 * kPi * k / 12), 0});
  for (int k = 0; k < 12; ++k) fan.polygons.push_back({0, 1 + k, 1 + (k + 1) % 12});
  const HlrResult cone = hidden_lines(two_sided_faces(fan), camera, options);
  EXPECT_EQ(cone.length(LineKind::Junction), 0);
  EXPECT_EQ(cone.stats.junction_segments, 0);
  EXPECT_NEAR(cone.length(LineKind::Edge), 12 * 2 * std::sin(kPi / 12), 1e-12);
}

// Regression (30 s of hidden lines for 400 buildings on a terrain of a million faces, 3 s for
// the terrain alone): a body of many faces in many pairs finds its faces and edges near each
// partner through a grid (Roberts::build_grids), not by testing all of them per pair. The
// junction lines of 9 boxes standing on a 40 × 40 terrain (3 200 triangles, one surface body)
// equal the sum of those of each box alone with it (far apart: none hides another's).
TEST(OpenSurfaceHiddenLines, ManyBodiesOnOneLargeSurfaceMeetItAsEachAloneDoes) {
  PolygonSoup soup;
  const int n = 40;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -2 + 4.0 * i / n, y = -2 + 4.0 * j / n;
      soup.vertices.emplace_back(x, y, 0.1 * std::sin(1.7 * x + 0.3) * std::cos(1.3 * y));
    }
  const auto at = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      soup.polygons.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      soup.polygons.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  const Body terrain = two_sided_surface(soup);
  std::vector<Body> boxes;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      boxes.push_back(box({a * 1.2 - 0.05 + 0.01 * b, b * 1.2 - 0.05, -0.3}, {a * 1.2 + 0.05, b * 1.2 + 0.05, 0.5}));
  const Camera camera = Camera::parallel({0.3, 0.2, -1});
  const HlrOptions options;
  std::vector<Body> all = {terrain};
  all.insert(all.end(), boxes.begin(), boxes.end());
  const HlrResult together = hidden_lines(all, camera, options);
  double alone = 0;
  int segments = 0;
  for (const Body& b : boxes) {
    const HlrResult r = hidden_lines(std::vector<Body>{terrain, b}, camera, options);
    alone += r.length(LineKind::Junction);
    segments += r.stats.junction_segments;
  }
  EXPECT_GT(alone, 9 * 0.2);  // each box's visible half of its 0.4 perimeter, about
  EXPECT_NEAR(together.length(LineKind::Junction), alone, 1e-12 * alone);
  EXPECT_EQ(together.stats.junction_segments, segments);
}

TEST(OpenSurfaceHiddenLines, SurfaceReachingBehindAPerspectiveEyeIsClippedAtTheNearPlane) {
  // Bug: a perspective eye standing over an open surface (a camera on a terrain) failed with
  // "a body needs at least 4 vertices": the near-plane split took each two-sided face for a
  // solid. A V valley z = 0.1·|x| over [−10, 10]², two faces meeting in the valley line x = 0,
  // seen from the eye (0, −5, 1) looking down the valley: everything in front of the near plane
  // is visible (every ray to the surface stays above it: z − 0.1·|x| = 1 − t along the ray to
  // a point of it). By hand: the far edge (two segments √101 long), the sides x = ±10 at z = 1
  // and the valley line from the near plane to y = 10; the cut along the near plane is no line.
  PolygonSoup soup;
  soup.vertices = {{-10, -10, 1}, {0, -10, 0}, {0, 10, 0}, {-10, 10, 1}, {10, -10, 1}, {10, 10, 1}};
  soup.polygons = {{0, 1, 2, 3}, {1, 4, 5, 2}};
  ASSERT_EQ(two_sided_faces(soup).size(), 2u);
  for (const auto& [form, faces] : both_forms(soup)) {
  SCOPED_TRACE(form);
  const Camera camera = Camera::perspective({0, -5, 1}, {0, 5, 0}, 60);
  Eigen::AlignedBox3d box(Vec3(-10, -10, 0), Vec3(10, 10, 1));
  const Plane near = camera.near_plane(box);
  // Where the near plane meets the line (x, y, z) for y free: value(x, 0, z) + y·n_y = 0.
  const auto y_near = [&](double x, double z) { return -near.value(Vec3(x, 0, z)) / near.normal().y(); };
  const double sides = 2 * (10 - y_near(10, 1)), valley = 10 - y_near(0, 0), far = 2 * std::sqrt(101.0);
  HlrOptions options;
  options.crease_angle = 5;  // the faces turn by 2·atan(0.1) = 11.4°: the valley is sharp
  const HlrResult sharp = hidden_lines(faces, camera, options);
  EXPECT_NEAR(sharp.length(LineKind::Edge), far + sides + valley, 1e-9);
  options.crease_angle = 30;  // smooth: the valley is not drawn, and not twice
  const HlrResult smooth = hidden_lines(faces, camera, options);
  EXPECT_NEAR(smooth.length(LineKind::Edge), far + sides, 1e-9);
  for (const HlrResult* r : {&sharp, &smooth})
    for (const HlrSegment& s : r->visible) {
      EXPECT_GE(near.value(s.a), -1e-12);
      EXPECT_GE(near.value(s.b), -1e-12);
    }
  }
}

// ---- Shadows: a terrain-like open grid over a ground slab ----

TEST(OpenSurfaceShadows, TerrainShadowOnGroundEqualsCgalUnionOfProjectedTriangles) {
  const int n = 6;
  PolygonSoup soup;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = 4.0 * i / n, y = 4.0 * j / n;
      soup.vertices.emplace_back(x, y, 1.5 + 0.4 * std::sin(1.3 * x) * std::cos(y));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      soup.polygons.push_back({a, a + 1, a + n + 2});
      soup.polygons.push_back({a, a + n + 2, a + n + 1});
    }
  // As given (face 0 up, turned to the light) and reversed (the light sees each face's other
  // side: a surface's triangle then occludes reversed, ShadowPiece::back_plane).
  PolygonSoup reversed = soup;
  for (auto& poly : reversed.polygons) std::reverse(poly.begin(), poly.end());
  for (const PolygonSoup* given : {&soup, &reversed})
  for (const auto& [form, faces] : both_forms(*given))
  for (const Vec3& d : {Vec3(0.35, 0.2, -1), Vec3(-0.5, 0.3, -0.8), Vec3(0.1, -0.7, -0.6)}) {
    SCOPED_TRACE(std::string(form) + (given == &soup ? ", as given" : ", reversed"));
    Scene scene;
    scene.add("ground", box({-6, -6, -1}, {10, 10, 0}));
    for (size_t i = 0; i < faces.size(); ++i) scene.add("t" + std::to_string(i), faces[i]);
    scene.lights = {Light::directional(d)};
    const ShadowResult r = compute_shadows(scene);
    int top = -1;
    const Body& ground = scene.get("ground").body;
    for (int f = 0; f < ground.face_count(); ++f)
      if (ground.inner_normal(f).z() < -0.5) top = f;
    const double got = r.face(0, 0, top).shadow_area;
    // Reference: the triangles projected onto z = 0 along d, united exactly by CGAL.
    std::vector<Ring2> rings;
    for (const auto& t : soup.polygons) {
      Ring2 ring;
      for (int v : t) {
        const Vec3& p = soup.vertices[static_cast<size_t>(v)];
        const Vec3 q = p - (p.z() / d.z()) * d;
        ring.emplace_back(q.x(), q.y());
      }
      rings.push_back(ring);
    }
    const double want = cgal_union(rings, false).area;
    EXPECT_NEAR(got, want, 1e-9 * want) << d.transpose();
    EXPECT_GT(want, 15);
    // Each terrain face: the side turned to the light receives, the other is self-shadowed.
    for (size_t i = 0; i < faces.size(); ++i)
      for (int f = 0; f < faces[i].face_count() / 2; ++f) {
        const FaceShadow& f0 = r.face(0, static_cast<int>(i) + 1, f);
        const FaceShadow& f1 = r.face(0, static_cast<int>(i) + 1, faces[i].twin_face(f));
        EXPECT_NE(f0.self_shadowed(), f1.self_shadowed());
      }
  }
}

// ---- Rendering: a single face covers its projected area, from either side ----

TEST(OpenSurfaceRender, SquareCoversItsProjectedPixelsFromBothSides) {
  const Body square = Body::two_sided_polygon({{0, 0, 0}, {2, 0, 0}, {2, 1.5, 0.5}, {0, 1.5, 0.5}});
  for (const Vec3& dir : {Vec3(0.3, 0.4, -1), Vec3(-0.2, -0.3, 1)}) {
    Scene scene;
    scene.add("square", square);
    scene.camera = Camera::parallel(dir);
    scene.lights = {Light::directional(Vec3(0.1, 0.2, dir.z() < 0 ? -1 : 1))};
    RenderOptions options;
    options.width = 200, options.height = 160;
    SampleRecord record;
    render(scene, options, &record);
    int covered = 0, face = -1;
    for (size_t s = 0; s < record.body.size(); ++s)
      if (record.body[s] == 0) ++covered, face = record.face[s];
    // Projected area in pixels (shoelace) and perimeter: coverage within half a pixel row along
    // the outline.
    double area = 0, perimeter = 0;
    const auto& v = square.vertices();
    for (size_t k = 0; k < v.size(); ++k) {
      const Eigen::Vector2d a = record.view.project(v[k]), b = record.view.project(v[(k + 1) % v.size()]);
      area += a.x() * b.y() - a.y() * b.x();
      perimeter += (b - a).norm();
    }
    area = std::abs(area) / 2;
    EXPECT_GT(area, 1000);
    EXPECT_NEAR(covered, area, perimeter) << dir.transpose();
    // The face turned to the camera is the one drawn: face 0 from above, face 1 from below.
    EXPECT_EQ(face, dir.z() < 0 ? 0 : 1);
  }
}

}  // namespace
}  // namespace hedra
