// Hidden lines, the visibility pass (hedra/visibility/roberts.h): stage 0 (facing, convex
// pieces, occlusion volumes, the picture grid) and stages 1–2 (each edge against its
// candidate occluders). Junction lines and coincident edges: junction_lines.cpp.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "hedra/core/error.h"
#include "hedra/core/parallel.h"
#include "hedra/core/tolerance.h"
#include "hedra/decompose/decompose.h"
#include "hedra/mesh/convexity.h"
#include "visibility/contour.h"
#include "visibility/model_incidence.h"
#include "visibility/roberts_internal.h"

namespace hedra::internal {
namespace {

void complement(const std::vector<TInterval>& parts, std::vector<TInterval>& out) {
  out.clear();
  double from = 0;
  for (const TInterval& p : parts) {
    if (p.first > from) out.emplace_back(from, p.first);
    from = std::max(from, p.second);
  }
  if (from < 1) out.emplace_back(from, 1.0);
}

// Conservative: false only when the segment surely misses the (inflated) box.
bool segment_meets_box(const Vec2& a, const Vec2& b, const Eigen::AlignedBox2d& box) {
  Eigen::AlignedBox2d sbox(a.cwiseMin(b), a.cwiseMax(b));
  if (!sbox.intersects(box)) return false;
  const Vec2 n(a.y() - b.y(), b.x() - a.x());
  const double c = n.dot(a);
  // The box is inflated by the culling margin; this test only needs to survive rounding.
  const double tol = 1e-12 * (std::abs(c) + n.cwiseAbs().dot(box.max().cwiseAbs().cwiseMax(box.min().cwiseAbs())));
  int pos = 0, neg = 0;
  for (const Vec2& q : {box.corner(Eigen::AlignedBox2d::BottomLeft), box.corner(Eigen::AlignedBox2d::BottomRight),
                        box.corner(Eigen::AlignedBox2d::TopLeft), box.corner(Eigen::AlignedBox2d::TopRight)}) {
    const double s = n.dot(q) - c;
    if (s > tol) ++pos;
    else if (s < -tol) ++neg;
    else return true;
  }
  return pos > 0 && neg > 0;
}

}  // namespace

HlrResult Roberts::run() {
  check_view();
  size_t edge_total = 0;
  for (const Body& body : bodies_) edge_total += static_cast<size_t>(body.edge_count());
  threads_ = edge_total < kSequentialEdges ? 1 : 0;
  // Stage 0: facing, pieces, occlusion volumes; the grid over the picture plane.
  meter_.stage(0, 0.2, static_cast<double>(bodies_.size()));
  prepare_bodies();
  build_index();
  meter_.finish_stage();
  meter_.stage(0.2, options_.junctions ? 0.9 : 1.0, static_cast<double>(edge_total));
  // Stages 1 and 2: the edges, bodies in parallel, results in body order.
  std::vector<EdgeOutput> outputs(bodies_.size());
  parallel_blocks(bodies_.size(), threads_, 8, [&](size_t begin, size_t end) {
    Scratch scratch;
    for (size_t b = begin; b != end; ++b) {
      edges_of(static_cast<int>(b), scratch, outputs[b]);
      outline_of(static_cast<int>(b), scratch, outputs[b]);
    }
  });
  size_t visible_total = 0, hidden_total = 0;
  for (const EdgeOutput& o : outputs) visible_total += o.visible.size(), hidden_total += o.hidden.size();
  result_.visible.reserve(visible_total);
  result_.hidden.reserve(hidden_total);
  for (EdgeOutput& o : outputs) {
    result_.visible.insert(result_.visible.end(), o.visible.begin(), o.visible.end());
    result_.hidden.insert(result_.hidden.end(), o.hidden.begin(), o.hidden.end());
    result_.stats.edges += o.stats.edges;
    result_.stats.back_edges += o.stats.back_edges;
    result_.stats.occlusion_tests += o.stats.occlusion_tests;
    result_.stats.exact_segments += o.stats.exact_segments;
    result_.stats.smooth_edges += o.stats.smooth_edges;
    result_.stats.outline_segments += o.stats.outline_segments;
  }
  meter_.finish_stage();
  if (options_.merge_coincident) merge_coincident();
  // Stage 3: junction lines.
  if (options_.junctions) {
    meter_.stage(0.9, 1.0, static_cast<double>(touching_pairs().size()));
    junctions();
    meter_.finish_stage();
  }
  // Outlines and smooth edges last: they take no part in the merging of coincident edges.
  for (const LineKind kind : {LineKind::Outline, LineKind::Smooth})
    for (const EdgeOutput& o : outputs)
      for (const HlrSegment& s : o.classes)
        if (s.kind == kind) result_.visible.push_back(s);
  result_.smooth_listed = options_.smooth;
  // The pieces' volumes freed on the workers: the destructor would free them one by one on
  // the calling thread, a serial O(pieces) tail of every call.
  parallel_blocks(pieces_.size(), threads_, 64, [&](size_t begin, size_t end) {
    for (size_t i = begin; i != end; ++i) {
      pieces_[i].volume = OcclusionVolume();
      pieces_[i].large.reset();
      std::vector<ExactPlane>().swap(pieces_[i].faces);
    }
  });
  return std::move(result_);
}

std::string Roberts::name(int body) const {
  return names_.empty() ? "body " + std::to_string(body) : "body '" + names_[static_cast<size_t>(body)] + "'";
}

void Roberts::check_view() {
  result_.picture_box.setEmpty();
  depth_range_ = Eigen::AlignedBox<double, 1>();
  depth_range_.setEmpty();
  // Bodies in parallel (every vertex is read: O(V) with V the scene's vertices), then the
  // first error in body order and the union of the boxes, as a serial pass would give.
  struct BodyView {
    Eigen::AlignedBox2d box;
    Eigen::AlignedBox<double, 1> depth;
    std::string error;
  };
  std::vector<BodyView> per_body(bodies_.size());
  parallel_blocks(bodies_.size(), threads_, 16, [&](size_t begin, size_t end) {
    for (size_t b = begin; b != end; ++b) {
      const Body& body = bodies_[b];
      BodyView& out = per_body[b];
      out.box.setEmpty();
      out.depth.setEmpty();
      if (projection_.perspective()) {
        if (body.bbox().contains(view_.point) && body.classify(view_.point) != Location::Outside) {
          out.error = name(static_cast<int>(b)) + ": the perspective eye lies " +
                      (body.classify(view_.point) == Location::Inside ? "inside" : "on") + " the body";
          continue;
        }
        bool bad = false;
        for (int v = 0; v < body.vertex_count() && !bad; ++v)
          if (!(projection_.depth(body.vertices()[static_cast<size_t>(v)]) > 0)) {
            out.error = name(static_cast<int>(b)) + ": vertex " + std::to_string(v) +
                        " is not in front of the perspective eye (hidden lines need the "
                        "whole scene in front of it)";
            bad = true;
          }
        if (bad) continue;
      }
      for (const Vec3& p : body.vertices()) {
        out.box.extend(projection_.project(p));
        Eigen::Matrix<double, 1, 1> d;
        d << projection_.depth(p);
        out.depth.extend(d);
      }
    }
  });
  for (const BodyView& v : per_body) {
    if (!v.error.empty()) throw InvalidInput(v.error);
    if (!v.box.isEmpty()) result_.picture_box.extend(v.box);
    if (!v.depth.isEmpty()) depth_range_.extend(v.depth);
  }
  if (result_.picture_box.isEmpty()) result_.picture_box.extend(Vec2::Zero());
  const double extent = std::max(result_.picture_box.sizes().maxCoeff(),
                                 result_.picture_box.min().cwiseAbs().maxCoeff() +
                                     result_.picture_box.max().cwiseAbs().maxCoeff());
  margin_ = kCullingMargin * std::max(extent, 1e-300);
  const double dmax = depth_range_.isEmpty() ? 1 : std::max(std::abs(depth_range_.min()(0)), std::abs(depth_range_.max()(0)));
  depth_margin_ = kCullingMargin * std::max(dmax, 1e-300);
}

Eigen::AlignedBox2d Roberts::picture_box(std::span<const Vec3> vertices) const {
  Eigen::AlignedBox2d box;
  box.setEmpty();
  for (const Vec3& p : vertices) box.extend(projection_.project(p));
  box.min().array() -= margin_;
  box.max().array() += margin_;
  return box;
}

double Roberts::near_depth(std::span<const Vec3> vertices) const {
  double d = INFINITY;
  for (const Vec3& p : vertices) d = std::min(d, projection_.depth(p));
  return d - depth_margin_;
}

void Roberts::prepare_bodies() {
  const bool brute = options_.stage2 == HlrOptions::Stage2::BruteForce;
  const size_t n = bodies_.size();
  data_.resize(n);
  result_.stats.bodies = static_cast<int>(n);
  // Stage 1 facing, convexity, and the pieces: a convex body is its own piece; others come
  // from the exact decomposition. Bodies in parallel, results in body order.
  struct BodyPieces {
    std::vector<Body> pieces;
    std::vector<FaceTriangle> triangles;  // faceted: the triangles of the front faces
    std::vector<std::vector<std::pair<int, int>>> planes;  // Decomposition::piece_planes
    std::vector<ExactConvex> exact;                        // Decomposition::exact_pieces
    std::vector<HlrFacet> facets;
    std::string error;
  };
  std::vector<BodyPieces> per_body(n);
  parallel_blocks(n, threads_, 8, [&](size_t begin, size_t end) {
    for (size_t b = begin; b != end; ++b) {
      const Body& body = bodies_[b];
      HlrBody& bd = data_[b];
      bd.facing.resize(static_cast<size_t>(body.face_count()));
      // Exact, about 7 ns a face: a large body's faces in parallel chunks.
      parallel_chunks(bd.facing.size(), kFacingChunk, [&](size_t, size_t lo, size_t hi) {
        for (size_t f = lo; f != hi; ++f) bd.facing[f] = facing(body, static_cast<int>(f), view_);
      });
      // Line classes: O(E) in double (a drawing construction, not a decision). A two-sided
      // face of an open surface gets its classes from the faces around it (surface_joins); a
      // surface of many faces (Body::two_sided_surface) from its own edges, its boundary edges
      // (joining a face to its other side) sharp.
      const bool one_face = body.two_sided() && body.face_count() == 2;
      if (options_.crease_angle > 0 && !one_face) {
        bd.classes = classify_edges(body, options_.crease_angle, surface(static_cast<int>(b)));
        bd.any_smooth = std::find(bd.classes.begin(), bd.classes.end(), EdgeClass::Smooth) != bd.classes.end();
      }
      // A two-sided face is its own convex piece; a two-sided surface occludes by its faces.
      bd.convex = one_face || (!body.two_sided() && is_convex(body));
      meter_.add();
      if (bd.convex) {
        // Faces off their planes: the convex polyhedron they bound cut into exactly planar
        // faces occludes, not their support planes, an ulp off it.
        std::optional<Body> split = exactly_planar_convex(body);
        if (!split) {
          per_body[b].pieces.push_back(body);
          continue;
        }
        bd.piece_facing.resize(static_cast<size_t>(split->face_count()));
        for (int f = 0; f < split->face_count(); ++f) bd.piece_facing[static_cast<size_t>(f)] = facing(*split, f, view_);
        per_body[b].pieces.push_back(std::move(*split));
        continue;
      }
      // Closed, seen from outside: the triangles turned to the viewpoint hide everything the
      // body hides (hedra/visibility/occlusion.h, Occluders::Faces).
      const auto occlude_by_faces = [&] {
        bd.faceted = true;
        per_body[b].triangles = front_triangles_of(body, bd.facing, view_);
        if (bd.any_smooth) {
          bd.vertex_faces.assign(static_cast<size_t>(body.vertex_count()), {});
          for (int f = 0; f < body.face_count(); ++f)
            for (const auto& loop : body.faces()[static_cast<size_t>(f)].loops)
              for (int v : loop) bd.vertex_faces[static_cast<size_t>(v)].push_back(f);
        }
      };
      if (body.two_sided() || (!brute && occludes_by_faces(body, options_.occluders))) {
        occlude_by_faces();
        continue;
      }
      try {
        DecomposeOptions decompose_options;
        decompose_options.exact_pieces = true;
        decompose_options.prefer_exact_solid = true;  // a moved body: every piece exactly convex
        if (meter_.active())
          decompose_options.progress = [this](int, int) {
            meter_.add(0);  // reports on the caller's thread, throws once cancelled
            return true;
          };
        Decomposition d = decompose(body, decompose_options);
        if (options_.occluders == Occluders::Auto && !brute && !pieces_exactly_convex(d)) {
          occlude_by_faces();  // exact on the body's triangles, not on a rounded piece
          continue;
        }
        per_body[b].pieces = std::move(d.pieces);
        per_body[b].planes = std::move(d.piece_planes);
        per_body[b].exact = std::move(d.exact_pieces);
        bd.input_planes = std::move(d.planes);
      } catch (const InvalidInput& e) {
        per_body[b].error = e.what();
        continue;
      }
      per_body[b].facets = facets_of(static_cast<int>(b), per_body[b].pieces);
    }
  });
  surface_joins();
  size_t count = 0;
  for (size_t b = 0; b < n; ++b) {
    if (!per_body[b].error.empty()) throw InvalidInput(name(static_cast<int>(b)) + ": " + per_body[b].error);
    count += per_body[b].pieces.size() + per_body[b].triangles.size();
  }
  pieces_.reserve(count);
  for (size_t b = 0; b < n; ++b) {
    for (const FaceTriangle& t : per_body[b].triangles) {
      pieces_.emplace_back(static_cast<int>(b), t.corners);
      pieces_.back().face = t.face;
    }
    for (size_t k = 0; k < per_body[b].pieces.size(); ++k) {
      pieces_.emplace_back(static_cast<int>(b), std::move(per_body[b].pieces[k]));
      const InputPlanes& model = data_[b].input_planes;
      if (k >= per_body[b].planes.size() || model.empty()) continue;
      // The exact piece's front faces: the viewpoint strictly on the outer side of the plane.
      HlrPiece& piece = pieces_.back();
      piece.exact = true;
      for (const auto& [c, sign] : per_body[b].planes[k]) {
        const Sign s = view_.at_infinity ? model.side_along(c, -view_.direction) : model.side(c, view_.point);
        if (static_cast<int>(s) * sign > 0) piece.front_planes.push_back(c);
      }
      if (k < per_body[b].exact.size() && !per_body[b].exact[k].faces.empty()) {
        // The exact piece's own planes: its volume is exact, so no end needs moving.
        piece.exact_piece = std::make_shared<const ExactConvex>(std::move(per_body[b].exact[k]));
        continue;
      }
      // Each rounded face's canonical plane, for the ends of hidden parts (end_snapped).
      piece.face_canonical = internal::rounded_face_planes(*piece.piece, per_body[b].planes[k], model);
    }
    for (HlrFacet& f : per_body[b].facets) facets_.push_back(std::move(f));
  }
  // Occlusion volumes and picture boxes of the pieces, in parallel.
  deferred_once_ = std::make_unique<std::once_flag[]>(pieces_.size());
  parallel_blocks(pieces_.size(), threads_, 16, [&](size_t begin, size_t end) {
    std::vector<Facing> piece_facing;
    for (size_t i = begin; i != end; ++i) {
      HlrPiece& p = pieces_[i];
      const HlrBody& bd = data_[static_cast<size_t>(p.body)];
      if (!p.piece) {
        // A triangle turned to the viewpoint (always, unless its face is planar only within a
        // tolerance): the volume from its corners, built on first use; else the two-sided
        // triangle as a Body.
        const auto& c = p.triangle;
        if (!brute && facing(triangle_plane(c), view_) == Facing::Front)
          p.deferred = true;
        else
          p.piece = Body::two_sided_polygon({c[0], c[1], c[2]});
      }
      if (p.piece) {
        const Body& piece = *p.piece;
        if (bd.convex && p.face < 0) {
          if (!brute && piece.face_count() >= kLargePieceFaces) p.large = std::make_unique<LargeConvex>();
          // A two-sided face (an open surface's): built on first use, as a front triangle's.
          // The boundary and outline of a surface of a million faces meet few of them.
          else if (!brute && piece.two_sided()) p.deferred = true;
          else build_volume(p);
        } else if (p.exact_piece) {
          p.volume = occlusion_volume(*p.exact_piece, view_);
        } else {
          piece_facing.clear();
          for (int f = 0; f < piece.face_count(); ++f) piece_facing.push_back(facing(piece, f, view_));
          p.volume = occlusion_volume(piece, piece_facing, view_);
        }
        if (brute && p.exact_piece)
          p.faces = p.exact_piece->faces;
        else if (brute)
          for (int f = 0; f < piece.face_count(); ++f) p.faces.push_back(exact_face_plane(piece, f));
      }
      p.box = picture_box(p.vertices());
      p.near = near_depth(p.vertices());
      p.occluder.body = p.body;
      if (!p.large) p.occluder.volume = p.volume.clipper ? &*p.volume.clipper : nullptr;
      p.occluder.faces = &p.faces;
    }
  });
  result_.stats.pieces = static_cast<int>(pieces_.size());
}

void Roberts::build_volume(const HlrPiece& p) const {
  p.volume = occlusion_volume(*p.piece, data_[static_cast<size_t>(p.body)].occluder_facing(), view_);
  p.occluder.volume = p.volume.clipper ? &*p.volume.clipper : nullptr;
}

const OcclusionVolume& Roberts::volume(const HlrPiece& p) const {
  if (p.large) std::call_once(p.large->volume_once, [&] { build_volume(p); });
  if (p.deferred)
    std::call_once(deferred_once_[static_cast<size_t>(&p - pieces_.data())], [&] {
      if (p.piece) {
        build_volume(p);  // a two-sided face
        return;
      }
      p.volume = triangle_occlusion_volume(p.triangle, triangle_plane(p.triangle), view_);
      p.occluder.volume = p.volume.clipper ? &*p.volume.clipper : nullptr;
    });
  return p.volume;
}

const LargeConvex& Roberts::silhouette_of(const HlrPiece& p) const {
  LargeConvex& l = *p.large;
  std::call_once(l.silhouette_once, [&] {
    const Body& body = *p.piece;
    l.silhouette = silhouette_volume(body, data_[static_cast<size_t>(p.body)].occluder_facing(), view_);
    // Each vertex projected once; each front face's picture box from its outer loop (the
    // holes lie inside it), inflated by the culling margin like the pieces' boxes.
    std::vector<Vec2> picture(body.vertices().size());
    for (size_t i = 0; i < picture.size(); ++i) picture[i] = projection_.project(body.vertices()[i]);
    Eigen::AlignedBox2d extent;
    extent.setEmpty();
    l.boxes.reserve(l.silhouette.front_faces.size());
    for (const int f : l.silhouette.front_faces) {
      Eigen::AlignedBox2d box;
      box.setEmpty();
      for (const int v : body.faces()[static_cast<size_t>(f)].loops[0]) box.extend(picture[static_cast<size_t>(v)]);
      box.min().array() -= margin_;
      box.max().array() += margin_;
      l.boxes.push_back(box);
      extent.extend(box);
    }
    l.grid.build(l.boxes, extent);
  });
  return l;
}

std::optional<SegmentPart> Roberts::hidden_part(const HlrPiece& p, const Vec3& p1, const Vec3& p2,
                                                Scratch& scratch) const {
  if (p.large) {
    const LargeConvex& l = silhouette_of(p);
    if (l.silhouette.front_faces.empty()) return std::nullopt;  // hides nothing
    if (l.silhouette.clipper) {
      const std::optional<SegmentPart> outer = clip_segment_open(*l.silhouette.clipper, p1, p2);
      if (!outer) return std::nullopt;
      // The front faces whose picture boxes the segment's picture meets: among them the face
      // each view ray through a point of the segment meets.
      const Vec2 a2 = projection_.project(p1), b2 = projection_.project(p2);
      std::vector<int>& ids = scratch.faces;
      ids.clear();
      l.grid.visit(Eigen::AlignedBox2d(a2.cwiseMin(b2), a2.cwiseMax(b2)), [&](int k) {
        if (segment_meets_box(a2, b2, l.boxes[static_cast<size_t>(k)])) ids.push_back(k);
      });
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      if (!ids.empty()) {
        std::vector<ExactPlane>& planes = scratch.front_planes.emplace_back();
        planes.reserve(ids.size());
        for (const int k : ids)
          planes.push_back(exact_face_plane(*p.piece, l.silhouette.front_faces[static_cast<size_t>(k)]));
        const std::optional<SegmentPart> inner = clip_segment_open(std::span<const ExactPlane>(planes), p1, p2);
        if (!inner) return std::nullopt;
        return intersect_parts(*outer, *inner, p1, p2);
      }
      // No face box met although the segment enters the silhouette: only rounding of the
      // boxes could do that; the whole volume decides.
    }
    // No silhouette plane (every silhouette edge's line through the viewpoint): the whole volume.
  }
  const OcclusionVolume& v = volume(p);
  if (!v.clipper) return std::nullopt;
  return clip_segment_open(*v.clipper, p1, p2);
}

void Roberts::surface_joins() {
  // Edges of two-sided faces (the faces of open surfaces), with their end points in
  // lexicographic order as the key. An edge that two such faces share in opposite directions
  // (a consistently oriented surface) is smooth when the faces are exactly coplanar (it lies
  // inside one flat region: a non-convex or holed face of the surface, cut into convex
  // two-sided faces, as an edge between coplanar faces of a solid is no edge of the drawing),
  // or, with a crease angle, when their normals turn by at most that angle (line classes, as
  // classify_edges does for a solid). Boundary edges and creases stay sharp. Either way the
  // edge is drawn once, by the first of the two faces (HlrBody::twin). Cost O(E log E).
  struct Key {
    std::array<double, 6> ends;
    int body, edge;
    bool forward;  // v0 → v1 runs from the smaller end point to the larger
  };
  std::vector<Key> keys;
  std::vector<int> sided;  // the two-sided bodies
  for (size_t b = 0; b < bodies_.size(); ++b) {
    const Body& body = bodies_[b];
    if (!body.two_sided() || body.face_count() > 2) continue;  // a surface joins its own faces
    sided.push_back(static_cast<int>(b));
    const auto& v = body.vertices();
    for (int e = 0; e < body.edge_count(); ++e) {
      const Edge& edge = body.edges()[static_cast<size_t>(e)];
      const Vec3 &p = v[static_cast<size_t>(edge.v0)], &q = v[static_cast<size_t>(edge.v1)];
      const bool forward = std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3);
      const Vec3& lo = forward ? p : q;
      const Vec3& hi = forward ? q : p;
      keys.push_back({{lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z()}, static_cast<int>(b), e, forward});
    }
  }
  if (sided.size() < 2) return;
  std::sort(keys.begin(), keys.end(), [](const Key& x, const Key& y) {
    return x.ends < y.ends || (x.ends == y.ends && std::tie(x.body, x.edge) < std::tie(y.body, y.edge));
  });
  const auto coplanar = [&](int a, int b) {
    const Body &A = bodies_[static_cast<size_t>(a)], &B = bodies_[static_cast<size_t>(b)];
    const auto &sa = A.support(0), &sb = B.support(0);
    const auto &va = A.vertices(), &vb = B.vertices();
    for (int k : sb)
      if (orient3d(va[static_cast<size_t>(sa[0])], va[static_cast<size_t>(sa[1])], va[static_cast<size_t>(sa[2])],
                   vb[static_cast<size_t>(k)]) != Sign::Zero)
        return false;
    return true;
  };
  // The outward unit normal of a two-sided face: its face 0, wound as the surface's polygon.
  const auto normal = [&](int b) { return Vec3(-bodies_[static_cast<size_t>(b)].inner_normal(0).normalized()); };
  const double cos_crease =
      options_.crease_angle > 0 ? std::cos(options_.crease_angle * std::numbers::pi / 180) : 2.0;
  const auto mark = [&](const Key& k, bool twin, bool smooth) {
    HlrBody& bd = data_[static_cast<size_t>(k.body)];
    const size_t edges = static_cast<size_t>(bodies_[static_cast<size_t>(k.body)].edge_count());
    if (smooth) {
      if (bd.classes.empty()) bd.classes.assign(edges, EdgeClass::Sharp);
      bd.classes[static_cast<size_t>(k.edge)] = EdgeClass::Smooth;
    }
    if (twin) {
      if (bd.twin.empty()) bd.twin.assign(edges, 0);
      bd.twin[static_cast<size_t>(k.edge)] = 1;
    }
  };
  bool any_crease_join = false;
  for (size_t i = 0, j; i < keys.size(); i = j) {
    for (j = i + 1; j < keys.size() && keys[j].ends == keys[i].ends; ++j) {
    }
    // Exactly two faces on the edge, in opposite directions.
    if (j - i != 2 || keys[i].forward == keys[i + 1].forward || keys[i].body == keys[i + 1].body) continue;
    // The edge is one line of the drawing: the second face leaves it to the first.
    const bool flat = coplanar(keys[i].body, keys[i + 1].body);
    const bool smooth = flat || normal(keys[i].body).dot(normal(keys[i + 1].body)) >= cos_crease;
    any_crease_join = any_crease_join || (smooth && !flat);
    mark(keys[i], false, smooth);
    mark(keys[i + 1], true, smooth);
  }
  if (any_crease_join) surface_outline(sided);
}

void Roberts::surface_outline(const std::vector<int>& sided) {
  // The outline of the open surfaces' smooth parts, as outline() for a solid: corner normals
  // area-weighted over the faces around the corner's point that turn from the face by at most
  // the crease angle; in each triangle of a face (a fan: the faces are convex) the segment
  // where g = n·r changes sign. Corners are the faces' vertices identified by their exact
  // coordinates (the surface's faces are separate bodies). Cost O(n log n) for n corners.
  struct Corner {
    Vec3 p;
    int slot, index;
  };
  std::vector<Corner> corners;
  std::vector<Vec3> normal(sided.size());
  std::vector<double> area(sided.size());
  for (size_t s = 0; s < sided.size(); ++s) {
    const Body& body = bodies_[static_cast<size_t>(sided[s])];
    normal[s] = -body.inner_normal(0).normalized();
    area[s] = body.face_area(0);
    const auto& loop = body.faces()[0].loops[0];
    for (size_t i = 0; i < loop.size(); ++i)
      corners.push_back({body.vertices()[static_cast<size_t>(loop[i])], static_cast<int>(s), static_cast<int>(i)});
  }
  std::sort(corners.begin(), corners.end(), [](const Corner& a, const Corner& b) {
    return std::lexicographical_compare(a.p.data(), a.p.data() + 3, b.p.data(), b.p.data() + 3);
  });
  // Point ids in lexicographic order; per face, its corners' point ids; per point, its faces.
  std::vector<std::vector<int>> point_of(sided.size());
  for (size_t s = 0; s < sided.size(); ++s)
    point_of[s].resize(bodies_[static_cast<size_t>(sided[s])].faces()[0].loops[0].size());
  std::vector<int> start{0}, around;
  for (size_t i = 0; i < corners.size(); ++i) {
    if (i > 0 && corners[i].p != corners[i - 1].p) start.push_back(static_cast<int>(around.size()));
    point_of[static_cast<size_t>(corners[i].slot)][static_cast<size_t>(corners[i].index)] =
        static_cast<int>(start.size()) - 1;
    around.push_back(corners[i].slot);
  }
  start.push_back(static_cast<int>(around.size()));
  const double cos_crease = std::cos(options_.crease_angle * std::numbers::pi / 180);
  // Face s's corner at point x: a corner whose faces within the crease angle all share s's
  // normal (a flat region, or a face alone at a crease) keeps it exactly: no contour there.
  const auto corner_normal = [&](size_t s, int x) {
    const Vec3& ns = normal[s];
    Vec3 sum = Vec3::Zero();
    bool flat = true;
    for (int k = start[static_cast<size_t>(x)]; k < start[static_cast<size_t>(x) + 1]; ++k) {
      const size_t g = static_cast<size_t>(around[static_cast<size_t>(k)]);
      if (!(normal[g].dot(ns) >= cos_crease)) continue;
      sum += area[g] * normal[g];
      flat = flat && (normal[g] - ns).cwiseAbs().maxCoeff() <= 1e-12;
    }
    return flat || !(sum.norm() > 0) ? ns : Vec3(sum.normalized());
  };
  std::vector<char> has(sided.size(), 0);
  parallel_chunks(sided.size(), 1024, [&](size_t, size_t lo, size_t hi) {
    std::vector<Vec3> p;
    std::vector<double> g;
    for (size_t s = lo; s != hi; ++s) {
      const Body& body = bodies_[static_cast<size_t>(sided[s])];
      const auto& loop = body.faces()[0].loops[0];
      const std::vector<int>& ids = point_of[s];
      const size_t k = loop.size();
      p.resize(k);
      g.resize(k);
      bool pos = false, neg = false;
      for (size_t i = 0; i < k; ++i) {
        p[i] = body.vertices()[static_cast<size_t>(loop[i])];
        g[i] = corner_normal(s, ids[i]).dot(view_.ray_to(p[i]));
        (g[i] >= 0 ? pos : neg) = true;
      }
      if (!pos || !neg) continue;
      // The fan from corner 0; crossings from the end with the smaller point id, so the face
      // across a side gets the same point (contour_segment, as outline() for a solid).
      std::vector<OutlineSegment>& out = data_[static_cast<size_t>(sided[s])].surface_outline;
      for (size_t t = 1; t + 1 < k; ++t) {
        const Vec3* corner[3] = {&p[0], &p[t], &p[t + 1]};
        const double gt[3] = {g[0], g[t], g[t + 1]};
        const int id[3] = {ids[0], ids[t], ids[t + 1]};
        Vec3 ends[2];
        if (contour_segment(corner, gt, id, ends)) out.push_back({ends[0], ends[1], 0});
      }
      has[s] = !out.empty();
    }
  });
  // The faces within two rings of a face with an outline: they approximate the smooth surface
  // the outline lies on, so they do not hide it (as outline_of() for a faceted solid).
  for (size_t s = 0; s < sided.size(); ++s) {
    if (!has[s]) continue;
    std::vector<int>& near = data_[static_cast<size_t>(sided[s])].surface_near;
    std::vector<int> ring;
    for (int x : point_of[s])
      for (int k = start[static_cast<size_t>(x)]; k < start[static_cast<size_t>(x) + 1]; ++k)
        ring.push_back(around[static_cast<size_t>(k)]);
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    for (int r : ring)
      for (int x : point_of[static_cast<size_t>(r)])
        for (int k = start[static_cast<size_t>(x)]; k < start[static_cast<size_t>(x) + 1]; ++k)
          near.push_back(sided[static_cast<size_t>(around[static_cast<size_t>(k)])]);
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
  }
}

std::vector<HlrFacet> Roberts::facets_of(int body, const std::vector<Body>& pieces) const {
  std::vector<HlrFacet> out;
  for (size_t i = 0; i < pieces.size(); ++i) {
    const Body& p = pieces[i];
    for (int fp = 0; fp < p.face_count(); ++fp) {
      if (facing(p, fp, view_) != Facing::EdgeOn) continue;
      const ExactPlane c = exact_face_plane(p, fp);
      for (size_t j = i + 1; j < pieces.size(); ++j) {
        const Body& q = pieces[j];
        if (!p.bbox().intersects(q.bbox())) continue;
        for (int fq = 0; fq < q.face_count(); ++fq) {
          const auto& s = q.support(fq);
          bool same_plane = true;
          for (int k : s) same_plane = same_plane && side_of_plane(c, q.vertices()[static_cast<size_t>(k)]) == Sign::Zero;
          if (!same_plane) continue;
          // Opposite sides: q's vertices off C lie on C's outer side.
          bool opposite = false;
          for (const Vec3& v : q.vertices()) {
            const Sign sv = side_of_plane(c, v);
            if (sv == Sign::Zero) continue;
            opposite = sv == Sign::Negative;
            break;
          }
          if (!opposite) continue;
          HlrFacet facet;
          facet.occluder.body = body;
          facet.occluder.plane = c;
          for (int f = 0; f < p.face_count(); ++f)
            if (f != fp) facet.occluder.bounds.push_back(exact_face_plane(p, f));
          for (int f = 0; f < q.face_count(); ++f)
            if (f != fq) facet.occluder.bounds.push_back(exact_face_plane(q, f));
          facet.box = picture_box(p.vertices()).merged(picture_box(q.vertices()));
          facet.near = std::min(near_depth(p.vertices()), near_depth(q.vertices()));
          out.push_back(std::move(facet));
        }
      }
    }
  }
  return out;
}

bool Roberts::edge_incident(const HlrPiece& p, int v0, int v1, int f1, int f2) const {
  const Body& body = bodies_[static_cast<size_t>(p.body)];
  const InputPlanes& m = data_[static_cast<size_t>(p.body)].input_planes;
  const Vec3 &s1 = body.vertices()[static_cast<size_t>(v0)], &s2 = body.vertices()[static_cast<size_t>(v1)];
  if (m.empty()) return rounded_incident(p, f1, f2, s1, s2);
  return incident(p, [&](int c) { return m.on(c, v0, s1) && m.on(c, v1, s2); }, f1, f2, s1, s2);
}

bool Roberts::face_incident(const HlrPiece& p, int f, const Vec3& s1, const Vec3& s2) const {
  const InputPlanes& m = data_[static_cast<size_t>(p.body)].input_planes;
  if (m.empty()) return rounded_incident(p, f, f, s1, s2);
  const std::vector<std::pair<int, int>>& planes = m.face_planes[static_cast<size_t>(f)];
  return incident(p, [&](int c) {
    return std::any_of(planes.begin(), planes.end(), [c](const std::pair<int, int>& q) { return q.first == c; });
  }, f, f, s1, s2);
}

bool Roberts::rounded_incident(const HlrPiece& p, int f1, int f2, const Vec3& s1, const Vec3& s2) const {
  const Body& body = bodies_[static_cast<size_t>(p.body)];
  const double tol = 8 * kRoundingPlanarity * body.scale();
  for (int g : volume(p).front_faces) {
    const Vec3 n = p.piece->plane(g).normal();
    for (int f : {f1, f2}) {
      const Plane& plane = body.plane(f);
      if (plane.normal().dot(n) <= 0.5) continue;
      bool on = true;
      for (int v : p.piece->faces()[static_cast<size_t>(g)].loops[0])
        on = on && std::abs(plane.value(p.piece->vertices()[static_cast<size_t>(v)])) <= tol;
      if (on) return true;
    }
  }
  const Vec3 d = s2 - s1;
  const double len = d.norm();
  if (len == 0) return false;
  const auto v = p.vertices();
  for (const auto& [a, b] : volume(p).silhouette)
    if ((v[static_cast<size_t>(a)] - s1).cross(d).norm() <= tol * len &&
        (v[static_cast<size_t>(b)] - s1).cross(d).norm() <= tol * len)
      return true;
  return false;
}

void Roberts::build_index() {
  std::vector<Eigen::AlignedBox2d> boxes;
  for (const HlrPiece& p : pieces_) boxes.push_back(p.box);
  for (const HlrFacet& f : facets_) boxes.push_back(f.box);
  grid_.build(boxes, result_.picture_box);
  result_.stats.grid_cells = grid_.cells();
  occluder_count_ = boxes.size();
  occluder_box_ = std::move(boxes);
  occluder_near_.clear();
  for (const HlrPiece& p : pieces_) occluder_near_.push_back(p.near);
  for (const HlrFacet& f : facets_) occluder_near_.push_back(f.near);
  by_near_.resize(pieces_.size());
  std::iota(by_near_.begin(), by_near_.end(), 0);
  std::sort(by_near_.begin(), by_near_.end(), [&](int x, int y) {
    const double nx = occluder_near_[static_cast<size_t>(x)], ny = occluder_near_[static_cast<size_t>(y)];
    return nx < ny || (nx == ny && x < y);
  });
  near_rank_.resize(pieces_.size());
  for (size_t r = 0; r < by_near_.size(); ++r) near_rank_[static_cast<size_t>(by_near_[r])] = static_cast<int>(r);
}

void Roberts::near_first(std::vector<int>& ids, Scratch& scratch) const {
  const int pieces = static_cast<int>(pieces_.size());
  const auto facet_start = facets_.empty() ? ids.end() : std::stable_partition(ids.begin(), ids.end(), [&](int id) { return id < pieces; });
  const size_t k = static_cast<size_t>(facet_start - ids.begin());
  if (k < 2) return;
  if (k * 16 < pieces_.size()) {
    std::sort(ids.begin(), facet_start, [&](int x, int y) {
      return near_rank_[static_cast<size_t>(x)] < near_rank_[static_cast<size_t>(y)];
    });
    return;
  }
  if (scratch.mark.size() != pieces_.size()) scratch.mark.assign(pieces_.size(), 0), scratch.mark_current = 0;
  const unsigned m = ++scratch.mark_current;
  for (auto it = ids.begin(); it != facet_start; ++it) scratch.mark[static_cast<size_t>(*it)] = m;
  auto out = ids.begin();
  for (int id : by_near_)
    if (scratch.mark[static_cast<size_t>(id)] == m) *out++ = id;
}

void Roberts::candidates(const Vec3& a, const Vec3& b, Scratch& scratch, std::vector<int>& out) const {
  out.clear();
  const Vec2 a2 = projection_.project(a), b2 = projection_.project(b);
  const double far = std::max(projection_.depth(a), projection_.depth(b));
  const auto consider = [&](int id) {
    if (occluder_near_[static_cast<size_t>(id)] >= far) return;  // wholly behind: cannot hide it
    if (!segment_meets_box(a2, b2, occluder_box_[static_cast<size_t>(id)])) return;
    out.push_back(id);
  };
  if (!options_.spatial_index || options_.stage2 == HlrOptions::Stage2::BruteForce) {
    for (int id = 0; id < static_cast<int>(occluder_count_); ++id) consider(id);
    return;
  }
  if (scratch.use_body_ids) {
    // The same set as the grid walk below: an occluder meeting the segment meets the body's
    // picture box, and the per-edge tests are the same.
    for (int id : scratch.body_ids) consider(id);
    return;
  }
  if (scratch.stamp.size() != occluder_count_) scratch.stamp.assign(occluder_count_, 0);
  const unsigned stamp = ++scratch.current;
  Eigen::AlignedBox2d box(a2.cwiseMin(b2), a2.cwiseMax(b2));
  grid_.visit(box, [&](int id) {
    if (scratch.stamp[static_cast<size_t>(id)] == stamp) return;
    scratch.stamp[static_cast<size_t>(id)] = stamp;
    consider(id);
  });
}

void Roberts::body_candidates(int b, Scratch& scratch) const {
  scratch.use_body_ids = false;
  scratch.body_ids.clear();
  // Facets keep the grid's visit order of the per-edge search (the exact path reads them in
  // that order); the reference paths have no grid.
  if (!options_.spatial_index || options_.stage2 == HlrOptions::Stage2::BruteForce || !facets_.empty()) return;
  const Body& body = bodies_[static_cast<size_t>(b)];
  Eigen::AlignedBox2d box;
  box.setEmpty();
  double far = -INFINITY;
  for (const Vec3& p : body.vertices()) {
    box.extend(projection_.project(p));
    far = std::max(far, projection_.depth(p));
  }
  // A body over many cells (a ground slab, a large mesh) would give each of its edges a long
  // list: its edges walk the grid themselves.
  if (grid_.covered(box) > 16) return;
  if (scratch.stamp.size() != occluder_count_) scratch.stamp.assign(occluder_count_, 0);
  const unsigned stamp = ++scratch.current;
  grid_.visit(box, [&](int id) {
    if (scratch.stamp[static_cast<size_t>(id)] == stamp) return;
    scratch.stamp[static_cast<size_t>(id)] = stamp;
    // Necessary conditions of candidates()' tests for any edge of the body: nearer than the
    // edge's far end (≤ the body's) and a box that meets the edge's box (⊂ the body's).
    if (occluder_near_[static_cast<size_t>(id)] >= far) return;
    if (!occluder_box_[static_cast<size_t>(id)].intersects(box)) return;
    scratch.body_ids.push_back(id);
  });
  scratch.use_body_ids = true;
}

bool Roberts::end_on(const Vec3& a, const Vec3& b) const {
  if (!view_.at_infinity) return collinear(a, b, view_.point);
  return parallel_to(a, b, view_.direction);
}

void Roberts::end_snapped(const HlrPiece& p, const EndVertices& ends, const Vec3& p1,
                          const Vec3& p2, std::optional<SegmentPart>& part) const {
  if (!part || !p.exact || p.large || p.body != ends.body) return;
  // An exact piece's volume is the exact piece's own, but the end vertex is the rounding of
  // a corner that lies on its face in the model (the exact image's decomposition: the vertex
  // an ulp off the exact plane), so a hidden part can end an ulp short of it.
  const bool exact_piece = p.exact_piece && !p.exact_piece->canonical.empty();
  if (!exact_piece && p.face_canonical.empty()) return;
  const OcclusionVolume& v = volume(p);
  if (!v.clipper) return;
  const std::vector<ExactPlane>& planes = v.clipper->planes();
  const InputPlanes& model = data_[static_cast<size_t>(p.body)].input_planes;
  const auto index = [&](const ExactPlane* plane) {
    return plane == nullptr ? std::ptrdiff_t{-1} : plane - planes.data();
  };
  // Whether the exact counterpart of volume plane i passes through end vertex w (at q).
  const auto through = [&](std::ptrdiff_t i, int w, const Vec3& q) {
    if (i < 0) return false;
    if (exact_piece) return internal::exact_volume_plane_through(v, static_cast<size_t>(i), *p.exact_piece, model, w, q);
    return internal::volume_plane_through(v, static_cast<size_t>(i), *p.piece, p.face_canonical, model, w, q);
  };
  // Every other plane holds on the part (lo, hi) strictly; where it also holds at the end
  // vertex (exactly on its rounded plane, or through the vertex in the model), it holds
  // strictly between the part's end and the vertex (an affine function), so the exact plane
  // through the vertex is the one that ends the part there.
  const auto others_hold = [&](std::ptrdiff_t skip, int w, const Vec3& q) {
    for (size_t i = 0; i < planes.size(); ++i)
      if (static_cast<std::ptrdiff_t>(i) != skip && side_of_plane(planes[i], q) == Sign::Negative &&
          !through(static_cast<std::ptrdiff_t>(i), w, q))
        return false;
    return true;
  };
  constexpr double kNear = 1e-6;  // rounding moves an end by ulps; never further than this
  SegmentPart& h = *part;
  // An end entering at the far vertex, or leaving at the near one: the exact part is empty.
  if ((h.lo.plane != nullptr && 1 - h.lo.t <= kNear && through(index(h.lo.plane), ends.v1, p2)) ||
      (h.hi.plane != nullptr && h.hi.t <= kNear && through(index(h.hi.plane), ends.v0, p1))) {
    part.reset();
    return;
  }
  if (h.hi.plane != nullptr && 1 - h.hi.t <= kNear && through(index(h.hi.plane), ends.v1, p2) &&
      others_hold(index(h.hi.plane), ends.v1, p2))
    h.hi = SegmentEnd{1, 0, nullptr};
  if (h.lo.plane != nullptr && h.lo.t <= kNear && through(index(h.lo.plane), ends.v0, p1) &&
      others_hold(index(h.lo.plane), ends.v0, p1))
    h.lo = SegmentEnd{0, 0, nullptr};
}

template <class Keep>
void Roberts::visible_parts(const Vec3& p1, const Vec3& p2, Keep&& keep, Scratch& scratch,
                            EdgeOutput& out, const EndVertices& ends) const {
  const bool brute = options_.stage2 == HlrOptions::Stage2::BruteForce;
  std::vector<int>& ids = scratch.ids;
  std::vector<SegmentPart>& parts = scratch.parts;
  detail::Candidates& exact = scratch.exact;
  candidates(p1, p2, scratch, ids);
  bool rational = brute;
  for (int id : ids)
    if (id >= static_cast<int>(pieces_.size())) {
      const auto& c = facets_[static_cast<size_t>(id) - pieces_.size()].occluder.plane;
      if (side_of_plane(c, p1) == Sign::Zero && side_of_plane(c, p2) == Sign::Zero) rational = true;
    }
  std::vector<TInterval>& visible = scratch.result;
  visible.clear();
  if (rational) {
    // In an internal cut plane seen edge-on (or the brute-force reference): exact path.
    ++out.stats.exact_segments;
    fill_candidates(ids, keep, exact);
    out.stats.occlusion_tests += static_cast<long long>(exact.pieces.size());
    visible = detail::visible_parts_exact(p1, p2, exact, view_, brute);
    return;
  }
  // Nearest pieces first: a piece that hides the whole segment ends the search.
  std::erase_if(ids, [&](int id) { return id >= static_cast<int>(pieces_.size()); });
  near_first(ids, scratch);
  parts.clear();
  scratch.front_planes.clear();  // the previous segment's (its parts are done)
  for (int id : ids) {
    const HlrPiece& o = pieces_[static_cast<size_t>(id)];
    if (!keep(o)) continue;
    if (!o.large && !volume(o).clipper) continue;
    ++out.stats.occlusion_tests;
    std::optional<SegmentPart> part = hidden_part(o, p1, p2, scratch);
    if (ends.body >= 0 && o.exact) end_snapped(o, ends, p1, p2, part);
    if (!part) continue;
    parts.push_back(*part);
    if (!part->lo.plane && !part->hi.plane) break;  // hidden whole
  }
  // Visible: the gaps between the merged hidden parts (exactly positive).
  merge_parts(parts, p1, p2);
  const std::vector<SegmentPart>& hidden = parts;
  SegmentEnd from{0, 0, nullptr};
  for (const SegmentPart& h : hidden) {
    if (compare_ends(from, h.lo, p1, p2) == Sign::Negative)
      visible.emplace_back(from.t, std::max(from.t, h.lo.t));
    from = h.hi;
  }
  if (compare_ends(from, SegmentEnd{1, 0, nullptr}, p1, p2) == Sign::Negative)
    visible.emplace_back(from.t, 1.0);
}

void Roberts::edges_of(int b, Scratch& scratch, EdgeOutput& out) const {
  const Body& body = bodies_[static_cast<size_t>(b)];
  const HlrBody& bd = data_[static_cast<size_t>(b)];
  const auto& v = body.vertices();
  body_candidates(b, scratch);
  const bool surface_body = body.two_sided() && body.face_count() > 2;
  const int sides = body.face_count() / 2;  // a two-sided body's faces of one side
  for (int e = 0; e < body.edge_count(); ++e) {
    if ((e & 63) == 63) meter_.add(64);  // HlrOptions::progress
    const Edge& edge = body.edges()[static_cast<size_t>(e)];
    const Vec3 &p1 = v[static_cast<size_t>(edge.v0)], &p2 = v[static_cast<size_t>(edge.v1)];
    // A smooth edge is drawn only when asked, as its own kind; one not drawn needs none of the
    // tests below (the exact coplanarity test of a million nearly coplanar facets cost a sixth
    // of hidden lines on a tessellated sphere).
    const bool smooth = !bd.classes.empty() && bd.classes[static_cast<size_t>(e)] == EdgeClass::Smooth;
    // An edge two faces of an open surface share is one edge: counted and drawn once, by the
    // first face (the second, its twin, would find the same parts: each face's edges lie on
    // the other's boundary, which hides nothing).
    if (!bd.twin.empty() && bd.twin[static_cast<size_t>(e)]) continue;
    // A two-sided surface has each edge between two of its faces on both sides: drawn once,
    // by the side turned to the viewpoint there: the front side's copy unless both its faces
    // are Back (then the other side's, whose faces are Front). A boundary edge joins the two
    // sides: one copy.
    if (surface_body && edge.left_face != body.twin_face(edge.right_face)) {
      const bool front_side = edge.left_face < sides;
      const int l = front_side ? edge.left_face : edge.left_face - sides;
      const int r = front_side ? edge.right_face : edge.right_face - sides;
      const bool both_back = bd.facing[static_cast<size_t>(l)] == Facing::Back &&
                             bd.facing[static_cast<size_t>(r)] == Facing::Back;
      if (front_side == both_back) continue;
    }
    if (smooth) {
      ++out.stats.smooth_edges;
      if (!options_.smooth) continue;
    }
    // Not an edge of the drawing: between two faces of one plane, or seen end-on.
    // A support vertex of the right face that is one of the left face's is on its plane: not
    // tested (orient3d of a repeated point is zero, but only exact arithmetic says so).
    const auto& sl = body.support(edge.left_face);
    bool coplanar = true;
    for (int k : body.support(edge.right_face))
      coplanar = coplanar && (k == sl[0] || k == sl[1] || k == sl[2] ||
                              orient3d(v[static_cast<size_t>(sl[0])], v[static_cast<size_t>(sl[1])],
                                              v[static_cast<size_t>(sl[2])], v[static_cast<size_t>(k)]) == Sign::Zero);
    // A two-sided face's edges join its two faces, which share one plane: all are drawn, as
    // a two-sided surface's boundary edges.
    if ((coplanar && !(body.two_sided() && edge.left_face == body.twin_face(edge.right_face))) || end_on(p1, p2))
      continue;
    if (!smooth) ++out.stats.edges;
    // Stage 1: an edge between two back faces is hidden by its own body.
    if (bd.facing[static_cast<size_t>(edge.left_face)] == Facing::Back &&
        bd.facing[static_cast<size_t>(edge.right_face)] == Facing::Back) {
      if (smooth) continue;
      ++out.stats.back_edges;
      if (options_.hidden) add_segment(out.hidden, p1, p2, LineKind::Edge, b, -1, e);
      continue;
    }
    // Stage 2: hidden parts by every piece that may cover the edge in the picture. A convex
    // body does not hide its own front and silhouette edges, so it is skipped.
    const int skip = bd.convex ? b : -1;
    // Pieces that may hide (part of) the edge: not its own convex body, not a piece of its
    // own body that it lies on (see incident()).
    const auto keep = [&](const HlrPiece& o) {
      if (o.body == skip) return false;
      if (o.body != b) return true;
      // A triangle of one of the edge's own faces: the edge lies on the face, not behind it
      // (a face planar only within rounding: its triangles are an ulp off each other); on a
      // two-sided surface, also of their other sides.
      if (o.face >= 0 && surface_body)
        return o.face != edge.left_face && o.face != edge.right_face &&
               o.face != body.twin_face(edge.left_face) && o.face != body.twin_face(edge.right_face);
      if (o.face >= 0) return o.face != edge.left_face && o.face != edge.right_face;
      return !edge_incident(o, edge.v0, edge.v1, edge.left_face, edge.right_face);
    };
    visible_parts(p1, p2, keep, scratch, out, EndVertices{b, edge.v0, edge.v1});
    const std::vector<TInterval>& visible = scratch.result;
    for (const TInterval& t : visible)
      add_segment(smooth ? out.classes : out.visible, point_at(p1, p2, t.first),
                  point_at(p1, p2, t.second), smooth ? LineKind::Smooth : LineKind::Edge, b, -1, e);
    if (options_.hidden && !smooth) {
      complement(visible, scratch.gaps);
      for (const TInterval& t : scratch.gaps)
        add_segment(out.hidden, point_at(p1, p2, t.first), point_at(p1, p2, t.second),
                    LineKind::Edge, b, -1, e);
    }
  }
  scratch.use_body_ids = false;
}

bool Roberts::outline_on_piece(const HlrPiece& p, const Vec3& n, const Vec3& a, const Vec3& b) const {
  const double tol = 64 * kRoundingPlanarity * bodies_[static_cast<size_t>(p.body)].scale();
  for (int f = 0; f < p.piece->face_count(); ++f) {
    const Plane& plane = p.piece->plane(f);
    // Piece planes have inner normals; n is outward.
    if (-plane.normal().dot(n) <= 0.5) continue;
    if (std::abs(plane.value(a)) <= tol && std::abs(plane.value(b)) <= tol) return true;
  }
  return false;
}

void Roberts::outline_of(int b, Scratch& scratch, EdgeOutput& out) const {
  const HlrBody& bd = data_[static_cast<size_t>(b)];
  if (!bd.surface_outline.empty()) {
    // A two-sided face's part of its surface's outline: not hidden by the faces around it.
    out.stats.outline_segments += static_cast<int>(bd.surface_outline.size());
    for (const OutlineSegment& s : bd.surface_outline) {
      if (s.a == s.b || end_on(s.a, s.b)) continue;
      const auto keep = [&](const HlrPiece& o) {
        return !std::binary_search(bd.surface_near.begin(), bd.surface_near.end(), o.body);
      };
      visible_parts(s.a, s.b, keep, scratch, out);
      for (const TInterval& t : scratch.result)
        add_segment(out.classes, point_at(s.a, s.b, t.first), point_at(s.a, s.b, t.second),
                    LineKind::Outline, b, -1, -1);
    }
    return;
  }
  if (!bd.any_smooth) return;
  const Body& body = bodies_[static_cast<size_t>(b)];
  const std::vector<OutlineSegment> segments =
      outline(body, view_, options_.crease_angle, surface(b));
  out.stats.outline_segments += static_cast<int>(segments.size());
  std::vector<int> near;
  // Faces at a smooth reflex edge of the body (the wall of a drilled hole): there the smooth
  // surface is concave, the outline is not on the silhouette of the piece it lies on, and that
  // piece's other faces (the plate's top beyond the hole's rim) do hide it. A sharp reflex
  // edge (a boss's foot on its plate) says nothing of the surface's curvature, and neither does
  // a turn below kConcaveTurn: a float32 export's side faces fold by ~1e-6 rad either way, a
  // tessellation's faces turn by 2·√(2t/r) ≥ 1e-3 rad down to a chordal error t of 1e-7 of the
  // radius r. A drawing construction, in double. Cost O(E), only with outlines.
  constexpr double kConcaveTurn = 1e-3;  // radians
  std::vector<char> concave;
  if (!bd.convex && !segments.empty()) {
    concave.assign(static_cast<size_t>(body.face_count()), 0);
    const std::vector<EdgeClass> classes = classify_edges(body, options_.crease_angle, surface(b));
    const auto& vs = body.vertices();
    for (size_t i = 0; i < body.edges().size(); ++i) {
      const Edge& e = body.edges()[i];
      if (classes[i] != EdgeClass::Smooth) continue;
      const Plane& left = body.plane(e.left_face);  // inner normal: outside is negative
      const Vec3 &a = vs[static_cast<size_t>(e.v0)], along = vs[static_cast<size_t>(e.v1)] - a;
      bool reflex = false;
      for (const auto& loop : body.faces()[static_cast<size_t>(e.right_face)].loops)
        for (int w : loop) {
          if (reflex || w == e.v0 || w == e.v1) continue;
          const Vec3& p = vs[static_cast<size_t>(w)];
          const double away = (p - a).cross(along).norm() / along.norm();  // from the edge's line
          reflex = -left.value(p) > kConcaveTurn * away;
        }
      if (reflex) concave[static_cast<size_t>(e.left_face)] = concave[static_cast<size_t>(e.right_face)] = 1;
    }
  }
  for (const OutlineSegment& s : segments) {
    if (s.a == s.b || end_on(s.a, s.b)) continue;
    // The outline lies on the body's surface where the view ray grazes it: a convex body never
    // hides it (as its silhouette edges); a piece of a non-convex body that has the segment's
    // face on its boundary neither (the contour is on its silhouette up to the chordal error),
    // unless the face is at a reflex edge (`concave`, above).
    const Vec3 n = -body.inner_normal(s.face);
    // Faceted: the faces within two rings of the segment's face approximate the smooth surface
    // the outline lies on (within the chordal error), so they do not hide it: near the
    // silhouette a face turned away lies under its neighbours in the picture by that error.
    near.clear();
    if (bd.faceted) {
      for (int v : body.faces()[static_cast<size_t>(s.face)].loops[0])
        for (int g : bd.vertex_faces[static_cast<size_t>(v)])
          for (int w : body.faces()[static_cast<size_t>(g)].loops[0])
            for (int h : bd.vertex_faces[static_cast<size_t>(w)]) near.push_back(h);
      std::sort(near.begin(), near.end());
      near.erase(std::unique(near.begin(), near.end()), near.end());
    }
    const auto keep = [&](const HlrPiece& o) {
      if (o.body != b) return true;
      // At a reflex smooth edge the faces around do hide it, as the pieces do (above).
      if (o.face >= 0) return concave[static_cast<size_t>(s.face)] || !std::binary_search(near.begin(), near.end(), o.face);
      return !bd.convex && (concave[static_cast<size_t>(s.face)] || !outline_on_piece(o, n, s.a, s.b));
    };
    visible_parts(s.a, s.b, keep, scratch, out);
    for (const TInterval& t : scratch.result)
      add_segment(out.classes, point_at(s.a, s.b, t.first), point_at(s.a, s.b, t.second),
                  LineKind::Outline, b, -1, -1);
  }
}

}  // namespace hedra::internal
