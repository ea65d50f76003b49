// Internals of hidden lines (hedra/visibility/roberts.h), shared by the visibility pass
// (hidden_lines.cpp: stages 0–2, the picture grid, the edges) and the junction lines
// (junction_lines.cpp: coincident edges and stage 3). The exact paths are in roberts_exact.h.
#pragma once

#include <algorithm>
#include <cmath>
#include <deque>
#include <memory>
#include <mutex>
#include <numeric>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <array>
#include <vector>

#include "hedra/clip/cyrus_beck.h"
#include "hedra/core/progress.h"
#include "hedra/decompose/decompose.h"
#include "hedra/visibility/outline.h"
#include "hedra/visibility/roberts.h"
#include "visibility/roberts_exact.h"

namespace hedra::internal {

using TInterval = std::pair<double, double>;

// ---- Spatial index: a uniform grid over the picture plane ----

class PictureGrid {
 public:
  // Cells about the mean size of the boxes (docs/algorithms.md §6.7: the course's N1·N2 cells of
  // about an edge's length), at most 4 per box.
  void build(const std::vector<Eigen::AlignedBox2d>& boxes, const Eigen::AlignedBox2d& extent) {
    origin_ = extent.min();
    const Vec2 size = extent.sizes().cwiseMax(1e-300);
    double cell = 0;
    int counted = 0;
    for (const auto& b : boxes)
      if (!b.isEmpty()) cell += b.sizes().maxCoeff(), ++counted;
    cell = counted ? cell / counted : size.maxCoeff();
    if (!(cell > 0)) cell = size.maxCoeff();
    const double max_cells = std::max<double>(16, 4.0 * static_cast<double>(boxes.size()));
    while ((size.x() / cell + 1) * (size.y() / cell + 1) > max_cells) cell *= 1.5;
    inv_ = 1 / cell;
    nx_ = std::max(1, static_cast<int>(std::ceil(size.x() * inv_)));
    ny_ = std::max(1, static_cast<int>(std::ceil(size.y() * inv_)));
    start_.assign(static_cast<size_t>(nx_) * ny_ + 1, 0);
    for (const auto& b : boxes) visit_cells(b, [&](size_t c) { ++start_[c + 1]; });
    std::partial_sum(start_.begin(), start_.end(), start_.begin());
    ids_.resize(static_cast<size_t>(start_.back()));
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < boxes.size(); ++i)
      visit_cells(boxes[i], [&](size_t c) { ids_[static_cast<size_t>(fill[c]++)] = static_cast<int>(i); });
  }

  // Calls f(id) for every box sharing a cell with `box` (an id may come several times).
  template <class F>
  void visit(const Eigen::AlignedBox2d& box, F&& f) const {
    visit_cells(box, [&](size_t c) {
      for (int k = start_[c]; k < start_[c + 1]; ++k) f(ids_[static_cast<size_t>(k)]);
    });
  }

  int cells() const { return nx_ * ny_; }

  // The number of cells `box` covers (0 for an empty box).
  long long covered(const Eigen::AlignedBox2d& box) const {
    long long n = 0;
    if (!box.isEmpty()) {
      const auto index = [&](double v, double o, int count) {
        const double c = std::floor((v - o) * inv_);
        return c < 0 ? 0 : (c >= count ? count - 1 : static_cast<int>(c));
      };
      n = static_cast<long long>(index(box.max().x(), origin_.x(), nx_) - index(box.min().x(), origin_.x(), nx_) + 1) *
          (index(box.max().y(), origin_.y(), ny_) - index(box.min().y(), origin_.y(), ny_) + 1);
    }
    return n;
  }

 private:
  template <class F>
  void visit_cells(const Eigen::AlignedBox2d& box, F&& f) const {
    if (box.isEmpty()) return;
    const auto index = [&](double v, double o, int n) {
      const double c = std::floor((v - o) * inv_);
      return c < 0 ? 0 : (c >= n ? n - 1 : static_cast<int>(c));
    };
    const int x0 = index(box.min().x(), origin_.x(), nx_), x1 = index(box.max().x(), origin_.x(), nx_);
    const int y0 = index(box.min().y(), origin_.y(), ny_), y1 = index(box.max().y(), origin_.y(), ny_);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) f(static_cast<size_t>(y) * nx_ + x);
  }

  Vec2 origin_ = Vec2::Zero();
  double inv_ = 1;
  int nx_ = 1, ny_ = 1;
  std::vector<int> start_, ids_;
};

// A convex body of many faces as an occluder (HlrPiece::large), built when a segment first
// needs it: the planes through its silhouette edges and its front faces in a grid over the
// picture. A point inside the silhouette planes is hidden exactly when it lies behind the
// front face its view ray meets (silhouette_volume), so a segment is clipped by the
// silhouette planes and the planes of the front faces its picture meets: O(silhouette + faces
// met) instead of O(front faces), and no front plane is built for a segment that misses the
// body. The full volume is built only for the exact paths (junction lines).
struct LargeConvex {
  std::once_flag volume_once, silhouette_once;
  OcclusionVolume silhouette;              // silhouette_volume()
  std::vector<Eigen::AlignedBox2d> boxes;  // picture boxes of silhouette.front_faces (inflated)
  PictureGrid grid;                        // over `boxes`
};

struct HlrPiece {
  HlrPiece(int b, Body p) : body(b), piece(std::move(p)) {}
  HlrPiece(int b, const std::array<Vec3, 3>& t) : body(b), triangle(t) {}
  int body = -1;
  // A convex piece; empty for a triangle of a body occluding by its faces, which keeps only
  // its corners (a million-face mesh: half a million triangles turned to the eye).
  std::optional<Body> piece;
  std::array<Vec3, 3> triangle{};
  std::span<const Vec3> vertices() const {
    if (piece) return piece->vertices();
    return triangle;
  }
  // The occlusion volume; read it through Roberts::volume(), which builds a deferred one.
  // A convex body of many faces (a tessellated sphere: 38 000 front planes, 6 MB) is `large`:
  // segments are clipped through its silhouette (LargeConvex), and the full volume is built
  // only if an exact path asks for it.
  mutable OcclusionVolume volume;
  mutable std::unique_ptr<LargeConvex> large;
  // A triangle turned to the viewpoint, or a two-sided face of an open surface, whose volume is
  // built on first use (Roberts::volume): a line drawing of a million-face mesh clips against
  // few of its half million front triangles (sharp edges and outlines only), and building them
  // all cost about 400 MB.
  bool deferred = false;
  std::vector<ExactPlane> faces;  // for the brute-force path
  // Pieces of a non-convex body: the canonical planes (Decomposition::piece_planes) of the
  // exact piece's faces turned to the viewpoint, decided exactly on their support triples;
  // `exact` false when the decomposition gave none (then the rounded tests decide).
  std::vector<int> front_planes;
  bool exact = false;
  // Per face of the rounded piece: the canonical plane of the exact piece's face it rounds
  // (the unambiguous match of their normals), or −1 (a face of the convex-hull fallback, a
  // sliver whose rounded normal is off). Read by end_snapped().
  std::vector<int> face_canonical;
  // The exact piece as planes (Decomposition::exact_pieces): when set, `volume` is built from
  // it (occlusion_volume(const ExactConvex&, …)), exact, and face_canonical stays empty.
  std::shared_ptr<const ExactConvex> exact_piece;
  // A triangle of a face of a body that occludes by its faces (Occluders::Faces): that face.
  int face = -1;
  mutable detail::PieceOccluder occluder;  // occluder.volume set with `volume`
  Eigen::AlignedBox2d box;
  double near = 0;  // least depth, minus the margin
};

struct HlrFacet {
  detail::FacetOccluder occluder;
  Eigen::AlignedBox2d box;
  double near = 0;
};

struct HlrBody {
  bool convex = true;
  std::vector<EdgeClass> classes;  // per edge; empty: every edge sharp (crease angle 0)
  bool any_smooth = false;
  std::vector<Facing> facing;
  // A convex body with faces off their planes: the facings of its one piece's faces
  // (exactly_planar_convex cuts those faces in two); empty when the piece is the body.
  std::vector<Facing> piece_facing;
  const std::vector<Facing>& occluder_facing() const { return piece_facing.empty() ? facing : piece_facing; }
  // Exact face planes (junctions), built on demand (a deque: stable). Allocated on first use:
  // an empty std::deque takes about 600 bytes, a body of an open surface of a million faces.
  std::unique_ptr<std::deque<ExactPlane>> planes;
  std::vector<int> plane_slot;     // per face: its index in planes, −1 not built yet
  InputPlanes input_planes;        // a non-convex body: its decomposition's exact planes
  // A non-convex body occluding by its faces (Occluders::Faces): its pieces are the triangles
  // of its faces turned to the viewpoint (HlrPiece::face).
  bool faceted = false;
  // faceted, with outlines: per vertex, the faces around it (outline_of's neighbourhood).
  std::vector<std::vector<int>> vertex_faces;
  // A two-sided face of an open surface (surface_joins): per edge, 1 where the face across the
  // shared edge draws it (empty: none); its part of the surface's
  // outline; and the faces within two rings of it, which do not hide that part.
  std::vector<char> twin;
  std::vector<OutlineSegment> surface_outline;
  std::vector<int> surface_near;
};

// The end vertices of a segment that is an edge (v0, v1) of body `body` (Roberts::visible_parts);
// -1 when it is not (an outline segment). At namespace scope: clang rejects a nested class's
// default member initializers in a default argument of its enclosing class.
struct EndVertices {
  int body = -1, v0 = -1, v1 = -1;
};

class Roberts {
 public:
  Roberts(std::span<const Body> bodies, std::span<const std::string> names,
          std::span<const SmoothSurface> surfaces, const Camera& camera, const HlrOptions& options)
      : bodies_(bodies), names_(names), surfaces_(surfaces), camera_(camera), options_(options),
        view_(Viewpoint::of(camera)), projection_(camera),
        meter_(options.progress, "hidden lines cancelled") {}

  HlrResult run();

 private:
  std::string name(int body) const;

  void check_view();

  // Open surfaces (two-sided faces): marks the edges their faces share inside one flat region,
  // or across a turn of at most the crease angle, as smooth (HlrBody::classes, twin), and
  // computes the outline of their smooth parts (surface_outline).
  void surface_joins();
  // The outline of the two-sided faces `sided` (HlrBody::surface_outline, surface_near).
  void surface_outline(const std::vector<int>& sided);
  Eigen::AlignedBox2d picture_box(std::span<const Vec3> vertices) const;

  double near_depth(std::span<const Vec3> vertices) const;

  void prepare_bodies();

  // Internal facets seen edge-on (detail::FacetOccluder): pairs of pieces of one body with
  // faces in one plane C, on opposite sides, C containing the viewpoint.
  std::vector<HlrFacet> facets_of(int body, const std::vector<Body>& pieces) const;

  // A segment of a non-convex body and a piece of the same body: does the segment lie on the
  // plane of a front face of the exact piece? Then it lies on the boundary of the exact piece's
  // open occlusion volume (a segment on the piece's silhouette lies on its front face too), and
  // the piece hides none of it: the rounded piece, which can be an ulp off, is not asked.
  // Decided in the decomposition's exact model: `on_plane(c)` says whether the segment lies on
  // canonical plane c (an edge: both end vertices on c, InputPlanes::on; a junction segment on
  // face f: c is a plane of f). Without the model (a decomposition that gave none), the rounded
  // test on faces f1 and f2 (rounded_incident). Cost O(front faces).
  template <class OnPlane>
  bool incident(const HlrPiece& p, OnPlane&& on_plane, int f1, int f2, const Vec3& s1,
                const Vec3& s2) const {
    if (!p.exact) return rounded_incident(p, f1, f2, s1, s2);
    // No front face: the exact piece hides nothing from this viewpoint.
    if (p.front_planes.empty()) return true;
    for (int c : p.front_planes)
      if (on_plane(c)) return true;
    return false;
  }
  // An edge (v0, v1) of body p.body, on its faces f1 and f2, against a piece of that body.
  bool edge_incident(const HlrPiece& p, int v0, int v1, int f1, int f2) const;
  // A segment s1s2 lying on face f of body p.body (a junction line) against a piece of it.
  bool face_incident(const HlrPiece& p, int f, const Vec3& s1, const Vec3& s2) const;
  // The fallback within rounding for pieces with faces rounding made: a front face of p within
  // 8·kRoundingPlanarity of the body's face f1 or f2, or a silhouette edge of p on the
  // segment's line within it.
  bool rounded_incident(const HlrPiece& p, int f1, int f2, const Vec3& s1, const Vec3& s2) const;

  void build_index();

  // Per-thread work space of the candidate search.
  struct Scratch {
    std::vector<unsigned> stamp;
    unsigned current = 0;
    std::vector<int> ids;
    std::vector<SegmentPart> parts;
    detail::Candidates exact;
    std::vector<TInterval> result;
    std::vector<TInterval> visible, gaps;
    std::vector<unsigned> mark;  // near_first(): pieces among the candidates
    unsigned mark_current = 0;
    // edges_of(): the occluders that may hide some edge of the current body (body_candidates),
    // which candidates() then filters per edge instead of walking the grid again.
    std::vector<int> body_ids;
    bool use_body_ids = false;
    // hidden_part() of large pieces: the front faces under the segment and their planes, kept
    // until the segment is done (its parts' ends point into them).
    std::vector<int> faces;
    std::deque<std::vector<ExactPlane>> front_planes;
  };

  // The occluders whose picture box meets body b's and that are nearer than its farthest
  // vertex: a superset of the candidates of each of its edges (an edge's picture box lies in
  // the body's), found with one walk of the grid per body instead of one per edge. Sets
  // scratch.use_body_ids when it applies (spatial index on, no internal facets, a body that
  // covers a few cells: a large body's edges walk the grid each, so that they keep O(k) tests).
  void body_candidates(int b, Scratch& scratch) const;

  // Orders the piece ids of `ids` nearest first (facet ids after them, in their order): a piece
  // that hides a whole segment ends its test early. O(k log k) for k candidates, or O(P) by a
  // walk of the pieces in near order when the candidates are a large share of the P pieces.
  void near_first(std::vector<int>& ids, Scratch& scratch) const;

  // Per-body output of stages 1 and 2.
  struct EdgeOutput {
    std::vector<HlrSegment> visible, hidden;
    std::vector<HlrSegment> classes;  // outlines, then smooth edges: added after the junctions
    HlrStats stats;
  };

  // A piece's occlusion volume, built on first use for a large piece (thread-safe).
  const OcclusionVolume& volume(const HlrPiece& p) const;
  // Builds p's volume (a convex body's own piece: from the body's facings).
  void build_volume(const HlrPiece& p) const;
  // One flag per piece, for the deferred triangles' volumes (HlrPiece::deferred).
  std::unique_ptr<std::once_flag[]> deferred_once_;
  // A large piece's silhouette and front-face grid, built on first use (thread-safe).
  const LargeConvex& silhouette_of(const HlrPiece& p) const;
  // The part of segment p1p2 hidden by piece p (open), or nullopt: through the silhouette for
  // a large piece, by the whole volume otherwise.
  std::optional<SegmentPart> hidden_part(const HlrPiece& p, const Vec3& p1, const Vec3& p2,
                                         Scratch& scratch) const;

  // Candidate occluders (piece ids, then facet ids offset by the piece count) for a segment.
  void candidates(const Vec3& a, const Vec3& b, Scratch& scratch, std::vector<int>& out) const;

  template <class Keep>
  void fill_candidates(const std::vector<int>& ids, Keep&& keep, detail::Candidates& out) const {
    out.pieces.clear();
    out.facets.clear();
    for (int id : ids) {
      if (id < static_cast<int>(pieces_.size())) {
        const HlrPiece& p = pieces_[static_cast<size_t>(id)];
        if (!keep(p)) continue;
        volume(p);  // a deferred volume built: occluder.volume points to it
        out.pieces.push_back(&p.occluder);
      } else {
        out.facets.push_back(&facets_[static_cast<size_t>(id) - pieces_.size()].occluder);
      }
    }
  }

  bool end_on(const Vec3& a, const Vec3& b) const;

  void add_segment(std::vector<HlrSegment>& list, const Vec3& a, const Vec3& b, LineKind kind,
                   int body, int other, int edge) const {
    if (a == b) return;
    HlrSegment s;
    s.a = a;
    s.b = b;
    s.a2 = projection_.project(a);
    s.b2 = projection_.project(b);
    s.kind = kind;
    s.body = body;
    s.other_body = other;
    s.edge = edge;
    list.push_back(s);
  }

  void edges_of(int b, Scratch& scratch, EdgeOutput& out) const;

  // Stage 2 for one segment of body b: the visible parts (t intervals) of p1p2 among the
  // candidate occluders that `keep` accepts. Cost O(k) clips for k candidates.
  template <class Keep>
  void visible_parts(const Vec3& p1, const Vec3& p2, Keep&& keep, Scratch& scratch,
                     EdgeOutput& out, const EndVertices& ends = {}) const;

  // The part of edge p1p2 that piece p of the edge's own body hides, with an end set by the
  // rounded plane of a front face or of a silhouette edge of p moved to the edge's end vertex
  // where the decomposition's model puts that vertex on the plane's exact counterpart
  // (internal::volume_plane_through): the exact plane passes through the vertex, so the hidden
  // part reaches it (an end `hi` at vertex v1, `lo` at v0), or, on the other side, is empty.
  // Rotated coordinates put the rounded plane an ulp off the vertex, which left visible slivers
  // of 1e-16 … 1e-13 at the ends of hidden edges. An end is moved only when every other plane
  // of p's volume holds at the vertex (on its rounded plane's inner side or boundary, or through
  // the vertex in the model), so the exact plane is the one that bounds the part there, and
  // when the rounded end lies within 1e-6 of the vertex's parameter. Cost O(planes) per end
  // moved, O(E) more for each silhouette plane asked.
  void end_snapped(const HlrPiece& p, const EndVertices& ends, const Vec3& p1, const Vec3& p2,
                   std::optional<SegmentPart>& part) const;

  // The outline of body b (when it has smooth parts), each segment clipped like an edge.
  void outline_of(int b, Scratch& scratch, EdgeOutput& out) const;

  // Whether piece p has a face on the plane of the body's face with outward unit normal n
  // through a and b (within rounding): an outline segment there is on the piece's boundary,
  // so the piece does not hide it. Cost O(faces of p).
  bool outline_on_piece(const HlrPiece& p, const Vec3& n, const Vec3& a, const Vec3& b) const;

  const SmoothSurface& surface(int b) const {
    static const SmoothSurface none;
    return surfaces_.empty() ? none : surfaces_[static_cast<size_t>(b)];
  }

  // Pairs of bodies whose boxes meet (closed), from a grid over the ground plane; computed once.
  const std::vector<std::pair<int, int>>& touching_pairs();

  std::vector<std::pair<int, int>> find_touching_pairs() const;

  // Edges of different bodies on one line: their parts are joined along the line.
  void merge_coincident();

  // The exact plane of face f of body b (junctions), built on first use. Not thread-safe.
  // The plane face_plane built already (read-only: safe on any thread).
  const ExactPlane& built_face_plane(int b, int f) const;
  const ExactPlane& face_plane(int b, int f);

  void junctions();

  // A body of many faces in grids over its two widest axes (PictureGrid), one of its faces and
  // one of its edges: its faces and edges near a partner's box come from the cells the box
  // covers instead of a test of every one of them in every pair (a terrain of a million faces
  // under 400 buildings: 30 s of hidden lines, 3 s without the buildings). Built for the bodies
  // of more than kGridFaces faces in at least kGridPartners touching pairs (a sphere on a slab
  // reads its faces once, as before), before the pairs run; null otherwise.
  struct BodyGrid {
    int u = 0, v = 1;  // the axes
    PictureGrid faces, edges;
    Eigen::AlignedBox2d flat(const Eigen::AlignedBox3d& box) const {
      return {Eigen::Vector2d(box.min()[u], box.min()[v]), Eigen::Vector2d(box.max()[u], box.max()[v])};
    }
  };
  static constexpr int kGridFaces = 256, kGridPartners = 4;
  std::vector<std::unique_ptr<BodyGrid>> grids_;
  void build_grids();
  // Faces (edges) of body b, which has a grid, whose boxes may meet `box`: ascending, once each
  // (a superset: the cells'). Cost O(cells covered + listed).
  std::vector<int> grid_faces(int b, const Eigen::AlignedBox3d& box) const;
  std::vector<int> grid_edges(int b, const Eigen::AlignedBox3d& box) const;

  std::span<const Body> bodies_;
  std::span<const std::string> names_;
  std::span<const SmoothSurface> surfaces_;
  Camera camera_;
  HlrOptions options_;
  Viewpoint view_;
  PictureProjection projection_;
  HlrResult result_;
  std::vector<HlrBody> data_;
  std::vector<HlrPiece> pieces_;
  std::vector<HlrFacet> facets_;
  PictureGrid grid_;
  size_t occluder_count_ = 0;
  // Picture box and near depth of every occluder (pieces, then facets), packed apart from the
  // large HlrPiece records so that the candidate search reads contiguous memory.
  std::vector<Eigen::AlignedBox2d> occluder_box_;
  std::vector<double> occluder_near_;
  std::vector<int> by_near_;    // piece ids by increasing near depth (ties by id)
  std::vector<int> near_rank_;  // position of each piece in by_near_
  std::optional<std::vector<std::pair<int, int>>> pairs_;
  double margin_ = 0, depth_margin_ = 0;
  Eigen::AlignedBox<double, 1> depth_range_;
  // HlrOptions::progress: decompositions, then edges, then junction pairs.
  mutable ProgressMeter meter_;
  // parallel_blocks' threads: 1 (no tasks) for a scene of fewer than kSequentialEdges edges,
  // where waking a second thread costs more than it saves (25 boxes: 0.119 ms on two threads,
  // 0.094 ms on one); 0 (the current arena) otherwise.
  static constexpr size_t kSequentialEdges = 512;
  // A body's faces decided in chunks of this many (one chunk, no task, below it).
  static constexpr size_t kFacingChunk = 8192;
  // A convex body of at least this many faces is a large piece (HlrPiece::large).
  static constexpr int kLargePieceFaces = 4096;
  int threads_ = 0;
};

}  // namespace hedra::internal
