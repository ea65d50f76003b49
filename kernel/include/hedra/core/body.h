// Body: a closed, consistently oriented polyhedron with planar polygonal faces, carrying its
// inner normals and body matrix. hedra's solid model (docs/algorithms.md §1).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "hedra/core/plane.h"
#include "hedra/core/predicates.h"
#include "hedra/core/transform.h"

namespace hedra {

class Body;
namespace internal {
struct ExactSolid;  // core/exact_solid.h (private)
void attach_exact_solid(Body& body, std::shared_ptr<const ExactSolid> solid);
}  // namespace internal

/// A planar face: loops[0] is the outer boundary, running counter-clockwise seen from
/// outside the body (so the right-hand normal points outwards); loops[1..] are holes, running
/// the other way. Faces with holes are supported directly (the cap of a plate with holes is
/// one face), not split into simple polygons. Entries are vertex indices.
struct Face {
  std::vector<std::vector<int>> loops;
  Face() = default;
  Face(std::initializer_list<int> outer) : loops{std::vector<int>(outer)} {}
  explicit Face(std::vector<int> outer) : loops{std::move(outer)} {}
  explicit Face(std::vector<std::vector<int>> all_loops) : loops(std::move(all_loops)) {}
};

/// An undirected edge; `v0 → v1` runs along `left_face`'s boundary and `v1 → v0` along
/// `right_face`'s.
struct Edge {
  int v0, v1;
  int left_face, right_face;
};

/// A triangle of a face's triangulation, counter-clockwise seen from outside.
struct Triangle {
  std::array<int, 3> v;
  int face;
};

/// Result of an exact point classification.
enum class Location { Inside, OnBoundary, Outside };

struct BodyOptions {
  /// Largest accepted distance of a face vertex from its face plane. Negative (the default)
  /// means "exact, up to the rounding of a construction": a face passes when its vertices are
  /// exactly coplanar, or within kRoundingPlanarity (tolerance.h) times the body's scale,
  /// which only rounded coordinates (rotations, tessellated spheres) need. Mesh import sets
  /// an explicit value when asked to.
  double planarity_tolerance = -1;
};

/// A validated solid. Value type: copies share the immutable geometry and derived data.
class Body {
 public:
  /// Builds and validates a body. Checks, in this order, with messages naming the place:
  /// finite coordinates within ±kMaxAbsCoordinate; faces of at least 3 vertices with indices
  /// in range and no repeated vertex; every vertex used; consistent orientation (each directed
  /// edge once); closed (each edge has both directions); manifold vertices; planar faces
  /// whose loops are simple and bound a region; no repeated faces; non-zero volume with
  /// outward-facing faces.
  /// \throw InvalidInput with a message such as "face 12 is not planar: vertex 40 is
  ///   3.1e-04 off its plane (tolerance 1.4e-14)". Cost O(V + E log E).
  Body(std::vector<Vec3> vertices, std::vector<Face> faces, const BodyOptions& options = {});

  const std::vector<Vec3>& vertices() const;
  const std::vector<Face>& faces() const;
  const std::vector<Edge>& edges() const;
  int vertex_count() const { return static_cast<int>(vertices().size()); }
  int face_count() const { return static_cast<int>(faces().size()); }
  int edge_count() const { return static_cast<int>(edges().size()); }

  /// Plane of face f with unit inner normal: interior points give a positive value.
  const Plane& plane(int f) const;
  Vec3 inner_normal(int f) const { return plane(f).normal(); }
  /// The body matrix V (4 × faces): column j is plane(j).coefficients. For a convex body this
  /// equals the course's matrix signed by the vertex average (docs/algorithms.md §1).
  const BodyMatrix& matrix() const;
  /// Three vertices of face f that define its exact supporting plane (outer-loop order, so
  /// orient3d(a, b, c, p) is Positive outside and Negative inside). Chosen once, well
  /// conditioned: all exact side-of-face decisions use them.
  const std::array<int, 3>& support(int f) const;
  /// Exact side of point p with respect to face f's supporting plane: Positive = inner side
  /// (the sign convention of the body matrix), Zero = on the plane. Cost O(1).
  Sign face_side(int f, const Vec3& p) const;
  /// Triangulation of every face (no zero-area triangles).
  const std::vector<Triangle>& triangles() const;
  /// The faces with a vertex off the plane of their support triple, accepted within the
  /// planarity tolerance (a file's rotated quadrilaterals: planar only within rounding),
  /// ascending; empty when every face is exactly planar. Exact consumers take such a face as
  /// exactly planar triangles: those of triangles() (the occluders of a non-convex body, its
  /// exact-planes decomposition), or, where the body is convex, the ones that keep it convex
  /// (convex_polygon_split in hedra/core/face_geometry.h: the convexity certificate, the
  /// occluders and receivers of hidden lines and shadows), which need not be the same.
  /// Recorded by the constructors' planarity checks (two-sided bodies' too): O(1).
  const std::vector<int>& faces_off_plane() const;
  /// Whether face f is in faces_off_plane(). Cost O(log of its size): O(1) when it is empty.
  bool face_off_plane(int f) const;

  double volume() const;
  double area() const;
  double face_area(int f) const;
  Vec3 centroid() const;
  const Eigen::AlignedBox3d& bbox() const;
  /// Largest |coordinate| or bounding-box diagonal: the scale tolerances refer to.
  double scale() const;

  /// Exact point classification against the triangulated boundary: OnBoundary when p lies on
  /// a face, else Inside/Outside by the parity of exact ray crossings (rays that graze an
  /// edge or vertex are replaced by another). Cost O(triangles).
  Location classify(const Vec3& p) const;

  /// The body moved by `t`. Reflections reverse the face loops so faces still face outwards.
  /// Perspective transforms are allowed when every vertex stays in front of the centre of
  /// projection (w > 0). \throw InvalidInput otherwise, or if the result is degenerate.
  Body transformed(const Transform& t) const;
  Body translated(const Vec3& d) const { return transformed(Transform::translation(d)); }
  Body scaled(const Vec3& k, const Vec3& centre = Vec3::Zero()) const {
    return transformed(Transform::scaling(k, centre));
  }
  Body rotated_x(double degrees, const Vec3& centre = Vec3::Zero()) const {
    return transformed(Transform::rotation_x(degrees, centre));
  }
  Body rotated_y(double degrees, const Vec3& centre = Vec3::Zero()) const {
    return transformed(Transform::rotation_y(degrees, centre));
  }
  Body rotated_z(double degrees, const Vec3& centre = Vec3::Zero()) const {
    return transformed(Transform::rotation_z(degrees, centre));
  }

  /// A two-sided face of an open surface (a scan, a terrain, a single face): the convex
  /// polygon `polygon` as a flat, closed body of two faces, face 0 running the given way
  /// (counter-clockwise seen from the side its right-hand normal points to) and face 1 the
  /// other way, with edge i from polygon[i] to polygon[i+1]. Seen from any point off its
  /// plane exactly one face is Front, so it occludes, receives shadows on the side facing a
  /// light, and is drawn two-sided by hidden lines, shadows and rendering, whose convex-piece
  /// code takes it as its own piece; decomposition and clipping reject it (it has no
  /// interior). volume() is 0, area() twice the polygon's area, classify() never says Inside.
  /// 	hrow InvalidInput unless the polygon has ≥ 3 finite vertices, is exactly planar and
  ///   strictly convex (no three consecutive vertices collinear). Cost O(n).
  /// `planarity_tolerance` > 0 also accepts vertices off the exact supporting plane by at most
  /// that distance (as BodyOptions: merged faces of a surface snapped within `--tolerance`);
  /// exact decisions still use the supporting triple.
  static Body two_sided_polygon(std::vector<Vec3> polygon, double planarity_tolerance = 0);
  /// An open surface (a scan, a terrain) as one flat, closed body: faces 0 … F−1 are the F
  /// given convex polygons (loops of indices into `vertices`, consistently oriented: each
  /// directed edge at most once), faces F … 2F−1 the same polygons reversed (face f + F is the
  /// other side of face f). An edge two faces share is an edge of each side (the front copy
  /// first); a boundary edge joins a face to its other side. Only the vertices the faces use
  /// are kept, renumbered in their order. Hidden lines, shadows and rendering take it as two
  /// sides of one surface, its faces occluding (hedra/visibility/occlusion.h,
  /// Occluders::Faces): a million faces are one body, not a million. Every face is tested as
  /// two_sided_polygon()'s, and `planarity_tolerance` means the same. volume() is 0, area()
  /// twice the surface's, classify() never says Inside.
  /// \throw InvalidInput naming the first face that is not a planar strictly convex polygon,
  ///   or the first edge used twice in one direction or by three faces.
  ///   Cost O(n + E log E) for n corners and E edges.
  static Body two_sided_surface(const std::vector<Vec3>& vertices,
                                const std::vector<std::vector<int>>& faces,
                                double planarity_tolerance = 0);
  /// True for two_sided_polygon() and two_sided_surface() bodies.
  bool two_sided() const;

  /// Whether this body is the rounding of an exact solid it keeps: a Boolean's result
  /// (hedra/mesh/boolean.h), a body with exactly planar faces (a box, a prism, any triangle
  /// mesh) moved by an affine transformed() — the exact image of its corners, made only when
  /// first needed — and any of these moved again by an affine map. Booleans on it start from
  /// the exact solid, and exact_volume_sign() measures it; its vertices are the exact corners
  /// rounded once (within half an ulp per coordinate). A perspective map, faces planar only
  /// within rounding (a tessellated sphere) and every other way of making a body give a body
  /// without one.
  bool has_exact_solid() const { return exact_solid() != nullptr; }
  /// The exact solid itself, for hedra's own layers (its type is private); null if none.
  const std::shared_ptr<const internal::ExactSolid>& exact_solid() const;
  /// The exact solid as bytes (empty if none), for a process boundary (Python's pickle, the
  /// distributed engine): a body rebuilt from its vertices and faces in another process gets it
  /// back with with_exact_solid_bytes(), so that what is decided on the solid there (the
  /// decomposition hidden lines and shadows clip against) is decided as here. A pending image
  /// stays pending (the first body's double corners and the maps); a made solid's corners are
  /// written as exact rationals. Cost O(n).
  std::string exact_solid_bytes() const;
  /// This body with the exact solid of `bytes` (exact_solid_bytes() of a body with the same
  /// vertices and faces); empty bytes: the body as it is. The structure is checked, not that
  /// the solid is this body's rounding: the bytes are trusted as a pickle is (fuzz target
  /// `solid`). \throw InvalidInput where the bytes are not such (truncated, another format,
  /// counts beyond the bytes, indices out of this body's range). Cost O(n).
  Body with_exact_solid_bytes(std::string_view bytes) const;
  /// A two-sided body's face on the other side of face f: f ± face_count() / 2.
  int twin_face(int f) const;

 private:
  // Memo of hedra/mesh/convexity.h's is_convex() verdict, shared by copies (the geometry is
  // immutable, so the verdict is too): −1 until first decided, then 0 or 1. Thread-safe.
  // Private: only is_convex() may read or record it, so no caller can plant a wrong verdict.
  friend bool is_convex(const Body& body);
  int convexity_memo() const;
  void set_convexity_memo(bool convex) const;
  friend void internal::attach_exact_solid(Body& body, std::shared_ptr<const internal::ExactSolid> solid);

  struct Impl;
  explicit Body(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<const Impl> impl_;
};

/// The combinatorial checks of Body's constructor alone (coordinates, face lists, used
/// vertices, orientation, closedness, manifold vertices), for raw data such as an imported
/// polygon soup, so messages name the input's own face and vertex numbers.
/// \throw InvalidInput. Cost O(V + E).
void check_polygon_mesh(const std::vector<Vec3>& vertices, const std::vector<Face>& faces);
/// The same checks on polygons of one loop each (a polygon soup), without copying them into
/// faces; the same messages as for faces. Returns each half-edge's twin: half-edges numbered
/// polygon by polygon, corner i of polygon p running from its vertex i to vertex i + 1;
/// every half-edge has one, as the surface is closed. Cost O(H log d) for H corners and
/// largest vertex degree d.
std::vector<int> check_polygon_mesh(const std::vector<Vec3>& vertices,
                                    const std::vector<std::vector<int>>& polygons);

/// Signs the columns of a plane matrix the course's way: each column is multiplied by −1
/// when the interior point s gives a negative value (docs/algorithms.md §1).
BodyMatrix sign_by_interior_point(BodyMatrix planes, const Vec3& s);

}  // namespace hedra
