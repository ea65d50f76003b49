#include "hedra/visibility/roberts.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>

#include "hedra/clip/cyrus_beck.h"
#include "hedra/decompose/decompose.h"
#include "visibility/roberts_exact.h"
#include "hedra/core/error.h"
#include "hedra/core/tolerance.h"

namespace hedra {

// ---- Picture plane ----

PictureProjection::PictureProjection(const Camera& camera) {
  perspective_ = camera.projection == Camera::Projection::Perspective;
  eye_ = camera.eye;
  axis_ = (perspective_ ? Vec3(camera.target - camera.eye) : camera.direction).normalized();
  right_ = axis_.cross(camera.up).normalized();
  up_ = right_.cross(axis_);
}

Vec2 PictureProjection::project(const Vec3& p) const {
  if (!perspective_) return {p.dot(right_), p.dot(up_)};
  const Vec3 q = p - eye_;
  const double d = q.dot(axis_);
  return {q.dot(right_) / d, q.dot(up_) / d};
}

double PictureProjection::depth(const Vec3& p) const {
  return perspective_ ? (p - eye_).dot(axis_) : p.dot(axis_);
}

double HlrResult::length(LineKind kind, bool visible_parts) const {
  double sum = 0;
  for (const HlrSegment& s : visible_parts ? visible : hidden)
    if (s.kind == kind) sum += (s.b - s.a).norm();
  return sum;
}

namespace {

// ---- Stage 2, fast path: the open part of a segment inside an occlusion volume ----

// An end of a hidden part: an exact end of the segment (plane == nullptr, t = 0 or 1) or the
// crossing of `plane`, t rounded with its error bound (hedra/clip/cyrus_beck.h).
struct End {
  double t = 0;
  double error = 0;
  const ExactPlane* plane = nullptr;
};

struct Part {
  End lo, hi;
};

Sign sign_of(const ExactPlane& f, const Vec3& p, double value, double bound) {
  if (value > bound) return Sign::Positive;
  if (value < -bound) return Sign::Negative;
  return side_of_plane(f, p);
}

// Exact order of two ends on segment p1p2. A crossing end lies strictly inside (0, 1): its
// plane separates the segment's end points strictly.
Sign compare(const End& a, const End& b, const Vec3& p1, const Vec3& p2) {
  if (!a.plane && !b.plane) return a.t < b.t ? Sign::Negative : (a.t > b.t ? Sign::Positive : Sign::Zero);
  if (!a.plane) return a.t == 0 ? Sign::Negative : Sign::Positive;
  if (!b.plane) return b.t == 0 ? Sign::Positive : Sign::Negative;
  if (a.plane == b.plane) return Sign::Zero;
  if (a.t - a.error > b.t + b.error) return Sign::Positive;
  if (a.t + a.error < b.t - b.error) return Sign::Negative;
  return compare_crossings(*a.plane, *b.plane, p1, p2);
}

// Sign of det[u, v, w] for u, v, w given exactly (differences computed here, rounded): a static
// filter in double (Shewchuk's bound for orient3d is (7 + 56u)u times the permanent; 1e-14
// leaves a wide margin), nullopt when it cannot decide.
std::optional<Sign> det3_filter(const Vec3& u, const Vec3& v, const Vec3& w) {
  const double m0 = v.y() * w.z() - v.z() * w.y(), m1 = v.z() * w.x() - v.x() * w.z(),
               m2 = v.x() * w.y() - v.y() * w.x();
  const double det = u.x() * m0 + u.y() * m1 + u.z() * m2;
  const double permanent = std::abs(u.x()) * (std::abs(v.y() * w.z()) + std::abs(v.z() * w.y())) +
                           std::abs(u.y()) * (std::abs(v.z() * w.x()) + std::abs(v.x() * w.z())) +
                           std::abs(u.z()) * (std::abs(v.x() * w.y()) + std::abs(v.y() * w.x()));
  if (!(permanent > 1e-250) || !(permanent < 1e250)) return std::nullopt;
  const double bound = 1e-14 * permanent;
  if (det > bound) return Sign::Positive;
  if (det < -bound) return Sign::Negative;
  return std::nullopt;
}

// orient3d with the static filter first.
Sign fast_orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  if (const auto s = det3_filter(b - a, c - a, d - a)) return *s;
  return orient3d(a, b, c, d);
}

// Facing of a face from its support triple (exactly as occlusion.h's facing()): the
// support triple's orient3d is Positive on the outer side.
Facing fast_facing(const Body& body, int face, const Viewpoint& view) {
  const auto& s = body.support(face);
  const Vec3 &a = body.vertices()[static_cast<size_t>(s[0])], &b = body.vertices()[static_cast<size_t>(s[1])],
             &c = body.vertices()[static_cast<size_t>(s[2])];
  Sign outward;  // moving along the direction (or the eye's side) is outward
  if (view.at_infinity) {
    const auto f = det3_filter(b - a, c - a, view.direction);
    outward = f ? *f : detail::orient_direction(a, b, c, view.direction);
    // Moving along d into the inner side: the ray enters through this face.
    return outward == Sign::Negative ? Facing::Front
                                     : (outward == Sign::Zero ? Facing::EdgeOn : Facing::Back);
  }
  outward = fast_orient3d(a, b, c, view.point);
  return outward == Sign::Positive ? Facing::Front
                                   : (outward == Sign::Zero ? Facing::EdgeOn : Facing::Back);
}

// The exact convexity test of hedra/mesh/convexity.h (no vertex off a face strictly outside its
// support plane; a face's own vertices, which rounding may put a few ulps off, are not
// tested), with the static filter.
bool fast_convex(const Body& body) {
  const auto& v = body.vertices();
  std::vector<int> stamp(v.size(), -1);
  for (int f = 0; f < body.face_count(); ++f) {
    for (const auto& loop : body.faces()[static_cast<size_t>(f)].loops)
      for (int i : loop) stamp[static_cast<size_t>(i)] = f;
    const auto& s = body.support(f);
    for (size_t i = 0; i < v.size(); ++i)
      if (stamp[i] != f && fast_orient3d(v[static_cast<size_t>(s[0])], v[static_cast<size_t>(s[1])],
                                         v[static_cast<size_t>(s[2])], v[i]) == Sign::Positive)
        return false;
  }
  return true;
}

// c = a + d when the sum is exact in every coordinate (TwoSum's error term is zero).
bool exact_sum(const Vec3& a, const Vec3& d, Vec3& c) {
  for (int i = 0; i < 3; ++i) {
    const double s = a[i] + d[i], bv = s - a[i];
    if ((a[i] - (s - bv)) + (d[i] - bv) != 0 || !std::isfinite(s)) return false;
    c[i] = s;
  }
  return true;
}

// The occlusion volume of a convex piece, the planes of occlusion.h's occlusion_volume()
// built with less work: facing by the static filter, front-face planes through the support
// triples (whose orientation rule, orient3d Positive outside, makes ExactPlane::through inner
// side Positive already), and each silhouette plane oriented by the vertex farthest from it in
// double, which the exact sign then confirms without an exact fallback.
OcclusionVolume occlusion_volume_of(const Body& body, const std::vector<Facing>& facing,
                                    const Viewpoint& view) {
  OcclusionVolume out;
  const auto& v = body.vertices();
  std::vector<ExactPlane> planes;
  planes.reserve(static_cast<size_t>(body.face_count() + body.edge_count()));
  out.front_faces.reserve(static_cast<size_t>(body.face_count()));
  out.silhouette.reserve(static_cast<size_t>(body.edge_count()));
  for (int f = 0; f < body.face_count(); ++f) {
    if (facing[static_cast<size_t>(f)] != Facing::Front) continue;
    out.front_faces.push_back(f);
    const auto& s = body.support(f);
    planes.push_back(ExactPlane::through(v[static_cast<size_t>(s[0])], v[static_cast<size_t>(s[1])],
                                         v[static_cast<size_t>(s[2])]));
  }
  if (out.front_faces.empty()) return out;
  for (const Edge& e : body.edges()) {
    if ((facing[static_cast<size_t>(e.left_face)] == Facing::Front) ==
        (facing[static_cast<size_t>(e.right_face)] == Facing::Front))
      continue;
    out.silhouette.emplace_back(e.v0, e.v1);
    const Vec3 &a = v[static_cast<size_t>(e.v0)], &b = v[static_cast<size_t>(e.v1)];
    ExactPlane plane;
    try {
      Vec3 c;
      if (!view.at_infinity)
        plane = ExactPlane::through(a, b, view.point);
      else if (exact_sum(a, view.direction, c))
        plane = ExactPlane::through(a, b, c);  // the same function: c − a = d exactly
      else
        plane = ExactPlane::through_direction(a, b, view.direction);
    } catch (const InvalidInput&) {
      continue;  // the viewpoint on the edge's line: the front face's plane bounds there
    }
    size_t far = 0;
    double best = -1;
    for (size_t i = 0; i < v.size(); ++i) {
      const double d = std::abs(plane.value(v[i]));
      if (d > best) best = d, far = i;
    }
    Sign side = side_of_plane(plane, v[far]);
    if (side == Sign::Zero)  // only for data at the limits of double: scan exactly
      for (const Vec3& p : v)
        if ((side = side_of_plane(plane, p)) != Sign::Zero) break;
    if (side == Sign::Zero) throw InvalidInput("occlusion volume: the body is flat");
    planes.push_back(side == Sign::Positive ? plane : plane.flipped());
  }
  out.clipper = ConvexClipper::from_planes(std::move(planes));
  return out;
}

// Cyrus–Beck for the open volume: every plane must be strictly positive. A plane that both
// ends are on or outside empties it (a segment in a bounding plane is not hidden); a plane
// with one end on it and the other inside bounds at that exact end.
std::optional<Part> clip_open(const ConvexClipper& clipper, const Vec3& p1, const Vec3& p2) {
  const double m1 = p1.cwiseAbs().maxCoeff(), m2 = p2.cwiseAbs().maxCoeff();
  End lo{0, 0, nullptr}, hi{1, 0, nullptr};
  for (const ExactPlane& f : clipper.planes()) {
    const double w = f.value(p1), e = f.value(p2);
    const double bw = f.error_bound(m1), be = f.error_bound(m2);
    const Sign s1 = sign_of(f, p1, w, bw), s2 = sign_of(f, p2, e, be);
    if (s1 != Sign::Positive && s2 != Sign::Positive) return std::nullopt;
    if (s1 == Sign::Positive && s2 == Sign::Positive) continue;
    if (s1 == Sign::Zero || s2 == Sign::Zero) continue;  // bounds at t = 0 or 1 exactly
    Crossing x = crossing_from_values(w, e, bw, be);
    if (!(x.t == x.t)) x = {0.5, 0.5};  // both values 0 in double: t within [0, 1]
    const End candidate{x.t, x.error, &f};
    if (s1 == Sign::Negative) {
      if (!lo.plane || compare(candidate, lo, p1, p2) == Sign::Positive) lo = candidate;
    } else if (!hi.plane || compare(candidate, hi, p1, p2) == Sign::Negative) {
      hi = candidate;
    }
  }
  if (compare(lo, hi, p1, p2) != Sign::Negative) return std::nullopt;
  if (lo.plane && hi.plane && hi.t < lo.t) hi.t = lo.t;  // rounding of ends within their bounds
  return Part{lo, hi};
}

// Sorts hidden parts and joins those that overlap or touch (exactly).
// In place.
void merge_parts(std::vector<Part>& parts, const Vec3& p1, const Vec3& p2) {
  if (parts.size() < 2) return;
  std::sort(parts.begin(), parts.end(), [&](const Part& a, const Part& b) {
    return compare(a.lo, b.lo, p1, p2) == Sign::Negative;
  });
  size_t last = 0;
  for (size_t i = 1; i < parts.size(); ++i) {
    Part& back = parts[last];
    if (compare(parts[i].lo, back.hi, p1, p2) != Sign::Positive) {
      if (compare(parts[i].hi, back.hi, p1, p2) == Sign::Positive) back.hi = parts[i].hi;
    } else {
      parts[++last] = parts[i];
    }
  }
  parts.resize(last + 1);
}

using TInterval = std::pair<double, double>;

void complement(const std::vector<TInterval>& parts, std::vector<TInterval>& out) {
  out.clear();
  double from = 0;
  for (const TInterval& p : parts) {
    if (p.first > from) out.emplace_back(from, p.first);
    from = std::max(from, p.second);
  }
  if (from < 1) out.emplace_back(from, 1.0);
}

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

struct PieceData {
  PieceData(int b, Body p) : body(b), piece(std::move(p)) {}
  int body = -1;
  Body piece;
  OcclusionVolume volume;
  std::vector<ExactPlane> faces;  // for the brute-force path
  // Pieces of a non-convex body: for each front face, the body's face it lies on (−1: a cut).
  std::vector<int> front_on_face;
  detail::PieceOccluder occluder;
  Eigen::AlignedBox2d box;
  double near = 0;  // least depth, minus the margin
};

struct FacetData {
  detail::FacetOccluder occluder;
  Eigen::AlignedBox2d box;
  double near = 0;
};

struct BodyData {
  bool convex = true;
  std::vector<Facing> facing;
  std::vector<ExactPlane> planes;  // exact face planes (junctions), filled on demand
};

class Roberts {
 public:
  Roberts(std::span<const Body> bodies, std::span<const std::string> names, const Camera& camera,
          const HlrOptions& options)
      : bodies_(bodies), names_(names), camera_(camera), options_(options),
        view_(Viewpoint::of(camera)), projection_(camera) {}

  HlrResult run() {
    check_view();
    // Stage 0: facing, pieces, occlusion volumes; the grid over the picture plane.
    prepare_bodies();
    build_index();
    // Stages 1 and 2: the edges, bodies in parallel, results in body order.
    {
      std::vector<EdgeOutput> outputs(bodies_.size());
      tbb::parallel_for(tbb::blocked_range<size_t>(0, bodies_.size(), 8),
                        [&](const tbb::blocked_range<size_t>& range) {
                          Scratch scratch;
                          for (size_t b = range.begin(); b != range.end(); ++b)
                            edges_of(static_cast<int>(b), scratch, outputs[b]);
                        });
      for (EdgeOutput& o : outputs) {
        result_.visible.insert(result_.visible.end(), o.visible.begin(), o.visible.end());
        result_.hidden.insert(result_.hidden.end(), o.hidden.begin(), o.hidden.end());
        result_.stats.edges += o.stats.edges;
        result_.stats.back_edges += o.stats.back_edges;
        result_.stats.occlusion_tests += o.stats.occlusion_tests;
        result_.stats.exact_segments += o.stats.exact_segments;
      }
    }
    if (options_.merge_coincident) merge_coincident();
    // Stage 3: junction lines.
    if (options_.junctions) junctions();
    return std::move(result_);
  }

 private:
  std::string name(int body) const {
    return names_.empty() ? "body " + std::to_string(body) : "body '" + names_[static_cast<size_t>(body)] + "'";
  }

  void check_view() {
    result_.picture_box.setEmpty();
    depth_range_ = Eigen::AlignedBox<double, 1>();
    depth_range_.setEmpty();
    for (size_t b = 0; b < bodies_.size(); ++b) {
      const Body& body = bodies_[b];
      if (projection_.perspective()) {
        if (body.bbox().contains(view_.point) && body.classify(view_.point) != Location::Outside)
          throw InvalidInput(name(static_cast<int>(b)) + ": the perspective eye lies " +
                             (body.classify(view_.point) == Location::Inside ? "inside" : "on") +
                             " the body");
        for (int v = 0; v < body.vertex_count(); ++v)
          if (!(projection_.depth(body.vertices()[static_cast<size_t>(v)]) > 0))
            throw InvalidInput(name(static_cast<int>(b)) + ": vertex " + std::to_string(v) +
                               " is not in front of the perspective eye (hidden lines need the "
                               "whole scene in front of it)");
      }
      for (const Vec3& p : body.vertices()) {
        result_.picture_box.extend(projection_.project(p));
        Eigen::Matrix<double, 1, 1> d;
        d << projection_.depth(p);
        depth_range_.extend(d);
      }
    }
    if (result_.picture_box.isEmpty()) result_.picture_box.extend(Vec2::Zero());
    const double extent = std::max(result_.picture_box.sizes().maxCoeff(),
                                   result_.picture_box.min().cwiseAbs().maxCoeff() +
                                       result_.picture_box.max().cwiseAbs().maxCoeff());
    margin_ = kCullingMargin * std::max(extent, 1e-300);
    const double dmax = depth_range_.isEmpty() ? 1 : std::max(std::abs(depth_range_.min()(0)), std::abs(depth_range_.max()(0)));
    depth_margin_ = kCullingMargin * std::max(dmax, 1e-300);
  }

  Eigen::AlignedBox2d picture_box(const Body& body) const {
    Eigen::AlignedBox2d box;
    box.setEmpty();
    for (const Vec3& p : body.vertices()) box.extend(projection_.project(p));
    box.min().array() -= margin_;
    box.max().array() += margin_;
    return box;
  }

  double near_depth(const Body& body) const {
    double d = INFINITY;
    for (const Vec3& p : body.vertices()) d = std::min(d, projection_.depth(p));
    return d - depth_margin_;
  }

  void prepare_bodies() {
    const bool brute = options_.stage2 == HlrOptions::Stage2::BruteForce;
    const size_t n = bodies_.size();
    data_.resize(n);
    result_.stats.bodies = static_cast<int>(n);
    // Stage 1 facing, convexity, and the pieces: a convex body is its own piece; others come
    // from the exact decomposition. Bodies in parallel, results in body order.
    struct BodyPieces {
      std::vector<Body> pieces;
      std::vector<FacetData> facets;
      std::string error;
    };
    std::vector<BodyPieces> per_body(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 8), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t b = range.begin(); b != range.end(); ++b) {
        const Body& body = bodies_[b];
        BodyData& bd = data_[b];
        bd.facing.resize(static_cast<size_t>(body.face_count()));
        for (int f = 0; f < body.face_count(); ++f) bd.facing[static_cast<size_t>(f)] = fast_facing(body, f, view_);
        bd.convex = fast_convex(body);
        if (bd.convex) {
          per_body[b].pieces.push_back(body);
          continue;
        }
        try {
          per_body[b].pieces = decompose(body).pieces;
        } catch (const InvalidInput& e) {
          per_body[b].error = e.what();
          continue;
        }
        per_body[b].facets = facets_of(static_cast<int>(b), per_body[b].pieces);
      }
    });
    size_t count = 0;
    for (size_t b = 0; b < n; ++b) {
      if (!per_body[b].error.empty()) throw InvalidInput(name(static_cast<int>(b)) + ": " + per_body[b].error);
      count += per_body[b].pieces.size();
    }
    pieces_.reserve(count);
    for (size_t b = 0; b < n; ++b) {
      for (Body& p : per_body[b].pieces) pieces_.emplace_back(static_cast<int>(b), std::move(p));
      for (FacetData& f : per_body[b].facets) facets_.push_back(std::move(f));
    }
    // Occlusion volumes and picture boxes of the pieces, in parallel.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pieces_.size(), 16), [&](const tbb::blocked_range<size_t>& range) {
      std::vector<Facing> piece_facing;
      for (size_t i = range.begin(); i != range.end(); ++i) {
        PieceData& p = pieces_[i];
        const BodyData& bd = data_[static_cast<size_t>(p.body)];
        if (bd.convex) {
          p.volume = occlusion_volume_of(p.piece, bd.facing, view_);
        } else {
          piece_facing.clear();
          for (int f = 0; f < p.piece.face_count(); ++f) piece_facing.push_back(fast_facing(p.piece, f, view_));
          p.volume = occlusion_volume_of(p.piece, piece_facing, view_);
          p.front_on_face = faces_on_body(p, bodies_[static_cast<size_t>(p.body)]);
        }
        if (brute)
          for (int f = 0; f < p.piece.face_count(); ++f) p.faces.push_back(exact_face_plane(p.piece, f));
        p.box = picture_box(p.piece);
        p.near = near_depth(p.piece);
        p.occluder.body = p.body;
        p.occluder.volume = p.volume.clipper ? &*p.volume.clipper : nullptr;
        p.occluder.faces = &p.faces;
      }
    });
    result_.stats.pieces = static_cast<int>(pieces_.size());
  }

  // Internal facets seen edge-on (detail::FacetOccluder): pairs of pieces of one body with
  // faces in one plane C, on opposite sides, C containing the viewpoint.
  std::vector<FacetData> facets_of(int body, const std::vector<Body>& pieces) const {
    std::vector<FacetData> out;
    for (size_t i = 0; i < pieces.size(); ++i) {
      const Body& p = pieces[i];
      for (int fp = 0; fp < p.face_count(); ++fp) {
        if (fast_facing(p, fp, view_) != Facing::EdgeOn) continue;
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
            FacetData facet;
            facet.occluder.body = body;
            facet.occluder.plane = c;
            for (int f = 0; f < p.face_count(); ++f)
              if (f != fp) facet.occluder.bounds.push_back(exact_face_plane(p, f));
            for (int f = 0; f < q.face_count(); ++f)
              if (f != fq) facet.occluder.bounds.push_back(exact_face_plane(q, f));
            facet.box = picture_box(p).merged(picture_box(q));
            facet.near = std::min(near_depth(p), near_depth(q));
            out.push_back(std::move(facet));
          }
        }
      }
    }
    return out;
  }

  // Which face of `body` each front face of piece p lies on, within the rounding that
  // decomposition and rotated coordinates leave (kRoundingPlanarity, as Body and decompose use).
  static std::vector<int> faces_on_body(const PieceData& p, const Body& body) {
    const double tol = 8 * kRoundingPlanarity * body.scale();
    std::vector<int> out;
    for (int g : p.volume.front_faces) {
      int found = -1;
      const Vec3 n = p.piece.plane(g).normal();
      for (int f = 0; f < body.face_count() && found < 0; ++f) {
        const Plane& plane = body.plane(f);
        if (plane.normal().dot(n) <= 0.5) continue;
        bool on = true;
        for (int v : p.piece.faces()[static_cast<size_t>(g)].loops[0])
          on = on && std::abs(plane.value(p.piece.vertices()[static_cast<size_t>(v)])) <= tol;
        if (on) found = f;
      }
      out.push_back(found);
    }
    return out;
  }

  // A segment of a non-convex body, lying on the body's faces f1 and f2, and a piece of the same
  // body: does the segment lie on a bounding plane of the piece's occlusion volume (a front face
  // on f1 or f2, or a silhouette edge on the segment's line)? Then the piece hides none of it.
  // Exact for exact coordinates; for rounded ones (a rotated body, whose decomposition's planes
  // and own vertices disagree by ulps) this is the incidence the geometry means.
  bool incident(const PieceData& p, int f1, int f2, const Vec3& s1, const Vec3& s2) const {
    for (size_t i = 0; i < p.front_on_face.size(); ++i)
      if (p.front_on_face[i] >= 0 && (p.front_on_face[i] == f1 || p.front_on_face[i] == f2)) return true;
    const Vec3 d = s2 - s1;
    const double len = d.norm();
    if (len == 0) return false;
    const double tol = 8 * kRoundingPlanarity * bodies_[static_cast<size_t>(p.body)].scale();
    const auto& v = p.piece.vertices();
    for (const auto& [a, b] : p.volume.silhouette)
      if ((v[static_cast<size_t>(a)] - s1).cross(d).norm() <= tol * len &&
          (v[static_cast<size_t>(b)] - s1).cross(d).norm() <= tol * len)
        return true;
    return false;
  }

  void build_index() {
    std::vector<Eigen::AlignedBox2d> boxes;
    for (const PieceData& p : pieces_) boxes.push_back(p.box);
    for (const FacetData& f : facets_) boxes.push_back(f.box);
    grid_.build(boxes, result_.picture_box);
    result_.stats.grid_cells = grid_.cells();
    occluder_count_ = boxes.size();
  }

  // Per-thread work space of the candidate search.
  struct Scratch {
    std::vector<unsigned> stamp;
    unsigned current = 0;
    std::vector<int> ids;
    std::vector<Part> parts;
    detail::Candidates exact;
    std::vector<TInterval> visible, gaps;
  };

  // Per-body output of stages 1 and 2.
  struct EdgeOutput {
    std::vector<HlrSegment> visible, hidden;
    HlrStats stats;
  };

  // Candidate occluders (piece ids, then facet ids offset by the piece count) for a segment.
  void candidates(const Vec3& a, const Vec3& b, Scratch& scratch, std::vector<int>& out) const {
    out.clear();
    const Vec2 a2 = projection_.project(a), b2 = projection_.project(b);
    const double far = std::max(projection_.depth(a), projection_.depth(b));
    const auto consider = [&](int id) {
      const bool piece = id < static_cast<int>(pieces_.size());
      const Eigen::AlignedBox2d& box = piece ? pieces_[static_cast<size_t>(id)].box
                                             : facets_[static_cast<size_t>(id) - pieces_.size()].box;
      const double near = piece ? pieces_[static_cast<size_t>(id)].near
                                : facets_[static_cast<size_t>(id) - pieces_.size()].near;
      if (near >= far) return;  // wholly behind the segment: cannot hide it
      if (!segment_meets_box(a2, b2, box)) return;
      out.push_back(id);
    };
    if (!options_.spatial_index || options_.stage2 == HlrOptions::Stage2::BruteForce) {
      for (int id = 0; id < static_cast<int>(occluder_count_); ++id) consider(id);
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

  template <class Keep>
  void fill_candidates(const std::vector<int>& ids, Keep&& keep, detail::Candidates& out) const {
    out.pieces.clear();
    out.facets.clear();
    for (int id : ids) {
      if (id < static_cast<int>(pieces_.size())) {
        const PieceData& p = pieces_[static_cast<size_t>(id)];
        if (keep(p)) out.pieces.push_back(&p.occluder);
      } else {
        out.facets.push_back(&facets_[static_cast<size_t>(id) - pieces_.size()].occluder);
      }
    }
  }

  bool end_on(const Vec3& a, const Vec3& b) const {
    if (!view_.at_infinity) return collinear(a, b, view_.point);
    // Filter: a clearly non-zero cross product decides; the exact test decides the rest.
    const Vec3 e = b - a;
    const Vec3 c = e.cross(view_.direction);
    if (c.cwiseAbs().maxCoeff() > 1e-10 * e.cwiseAbs().maxCoeff() * view_.direction.cwiseAbs().maxCoeff())
      return false;
    return detail::parallel_to(a, b, view_.direction);
  }

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

  void edges_of(int b, Scratch& scratch, EdgeOutput& out) const {
    const Body& body = bodies_[static_cast<size_t>(b)];
    const BodyData& bd = data_[static_cast<size_t>(b)];
    const auto& v = body.vertices();
    const bool brute = options_.stage2 == HlrOptions::Stage2::BruteForce;
    std::vector<int>& ids = scratch.ids;
    std::vector<Part>& parts = scratch.parts;
    detail::Candidates& exact = scratch.exact;
    for (int e = 0; e < body.edge_count(); ++e) {
      const Edge& edge = body.edges()[static_cast<size_t>(e)];
      const Vec3 &p1 = v[static_cast<size_t>(edge.v0)], &p2 = v[static_cast<size_t>(edge.v1)];
      // Not an edge of the drawing: between two faces of one plane, or seen end-on.
      const auto& sl = body.support(edge.left_face);
      bool coplanar = true;
      for (int k : body.support(edge.right_face))
        coplanar = coplanar && fast_orient3d(v[static_cast<size_t>(sl[0])], v[static_cast<size_t>(sl[1])],
                                             v[static_cast<size_t>(sl[2])], v[static_cast<size_t>(k)]) == Sign::Zero;
      if (coplanar || end_on(p1, p2)) continue;
      ++out.stats.edges;
      // Stage 1: an edge between two back faces is hidden by its own body.
      if (bd.facing[static_cast<size_t>(edge.left_face)] == Facing::Back &&
          bd.facing[static_cast<size_t>(edge.right_face)] == Facing::Back) {
        ++out.stats.back_edges;
        if (options_.hidden) add_segment(out.hidden, p1, p2, LineKind::Edge, b, -1, e);
        continue;
      }
      // Stage 2: hidden parts by every piece that may cover the edge in the picture. A convex
      // body does not hide its own front and silhouette edges, so it is skipped.
      candidates(p1, p2, scratch, ids);
      const int skip = bd.convex ? b : -1;
      // Pieces that may hide (part of) the edge: not its own convex body, not a piece of its
      // own body that it lies on (see incident()).
      const auto keep = [&](const PieceData& o) {
        if (o.body == skip) return false;
        return o.body != b || !incident(o, edge.left_face, edge.right_face, p1, p2);
      };
      bool rational = brute;
      for (int id : ids)
        if (id >= static_cast<int>(pieces_.size())) {
          const auto& c = facets_[static_cast<size_t>(id) - pieces_.size()].occluder.plane;
          if (side_of_plane(c, p1) == Sign::Zero && side_of_plane(c, p2) == Sign::Zero) rational = true;
        }
      std::vector<TInterval>& visible = scratch.visible;
      visible.clear();
      if (rational) {
        // In an internal cut plane seen edge-on (or the brute-force reference): exact path.
        ++out.stats.exact_segments;
        fill_candidates(ids, keep, exact);
        out.stats.occlusion_tests += static_cast<long long>(exact.pieces.size());
        visible = detail::visible_parts_exact(p1, p2, exact, view_, brute);
      } else {
        // Nearest pieces first: a piece that hides the whole edge ends the search.
        std::erase_if(ids, [&](int id) { return id >= static_cast<int>(pieces_.size()); });
        std::sort(ids.begin(), ids.end(), [&](int x, int y) {
          return pieces_[static_cast<size_t>(x)].near < pieces_[static_cast<size_t>(y)].near;
        });
        parts.clear();
        for (int id : ids) {
          const PieceData& o = pieces_[static_cast<size_t>(id)];
          if (!o.volume.clipper || !keep(o)) continue;
          ++out.stats.occlusion_tests;
          const std::optional<Part> part = clip_open(*o.volume.clipper, p1, p2);
          if (!part) continue;
          parts.push_back(*part);
          if (!part->lo.plane && !part->hi.plane) break;  // hidden whole
        }
        // Visible: the gaps between the merged hidden parts (exactly positive).
        merge_parts(parts, p1, p2);
        const std::vector<Part>& hidden = parts;
        End from{0, 0, nullptr};
        for (const Part& h : hidden) {
          if (compare(from, h.lo, p1, p2) == Sign::Negative)
            visible.emplace_back(from.t, std::max(from.t, h.lo.t));
          from = h.hi;
        }
        if (compare(from, End{1, 0, nullptr}, p1, p2) == Sign::Negative)
          visible.emplace_back(from.t, 1.0);
      }
      for (const TInterval& t : visible)
        add_segment(out.visible, point_at(p1, p2, t.first), point_at(p1, p2, t.second),
                    LineKind::Edge, b, -1, e);
      if (options_.hidden) {
        complement(visible, scratch.gaps);
        for (const TInterval& t : scratch.gaps)
          add_segment(out.hidden, point_at(p1, p2, t.first), point_at(p1, p2, t.second),
                      LineKind::Edge, b, -1, e);
      }
    }
  }

  // Pairs of bodies whose boxes meet (closed), by sweeping along x; computed once.
  const std::vector<std::pair<int, int>>& touching_pairs() {
    if (!pairs_) pairs_ = find_touching_pairs();
    return *pairs_;
  }

  std::vector<std::pair<int, int>> find_touching_pairs() const {
    std::vector<int> order(bodies_.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int x, int y) {
      return bodies_[static_cast<size_t>(x)].bbox().min().x() < bodies_[static_cast<size_t>(y)].bbox().min().x();
    });
    std::vector<std::pair<int, int>> out;
    for (size_t i = 0; i < order.size(); ++i) {
      const auto& bi = bodies_[static_cast<size_t>(order[i])].bbox();
      for (size_t j = i + 1; j < order.size(); ++j) {
        const auto& bj = bodies_[static_cast<size_t>(order[j])].bbox();
        if (bj.min().x() > bi.max().x()) break;
        if (bi.intersects(bj)) out.emplace_back(std::min(order[i], order[j]), std::max(order[i], order[j]));
      }
    }
    std::sort(out.begin(), out.end());
    return out;
  }

  // Edges of different bodies on one line: their parts are joined along the line.
  void merge_coincident() {
    const auto& pairs = touching_pairs();
    if (pairs.empty()) return;
    // Union-find over (body, edge).
    std::vector<int> offset(bodies_.size() + 1, 0);
    for (size_t b = 0; b < bodies_.size(); ++b) offset[b + 1] = offset[b] + bodies_[b].edge_count();
    std::vector<int> parent(static_cast<size_t>(offset.back()));
    std::iota(parent.begin(), parent.end(), 0);
    const std::function<int(int)> find = [&](int x) {
      while (parent[static_cast<size_t>(x)] != x) x = parent[static_cast<size_t>(x)] = parent[static_cast<size_t>(parent[static_cast<size_t>(x)])];
      return x;
    };
    bool any = false;
    for (const auto& [i, j] : pairs) {
      const Body &a = bodies_[static_cast<size_t>(i)], &b = bodies_[static_cast<size_t>(j)];
      for (int ea = 0; ea < a.edge_count(); ++ea) {
        const Edge& x = a.edges()[static_cast<size_t>(ea)];
        const Vec3 &a0 = a.vertices()[static_cast<size_t>(x.v0)], &a1 = a.vertices()[static_cast<size_t>(x.v1)];
        const Eigen::AlignedBox3d box_a(a0.cwiseMin(a1), a0.cwiseMax(a1));
        if (!box_a.intersects(b.bbox())) continue;
        for (int eb = 0; eb < b.edge_count(); ++eb) {
          const Edge& y = b.edges()[static_cast<size_t>(eb)];
          const Vec3 &b0 = b.vertices()[static_cast<size_t>(y.v0)], &b1 = b.vertices()[static_cast<size_t>(y.v1)];
          if (!box_a.intersects(Eigen::AlignedBox3d(b0.cwiseMin(b1), b0.cwiseMax(b1)))) continue;
          if (!collinear(a0, a1, b0) || !collinear(a0, a1, b1)) continue;
          parent[static_cast<size_t>(find(offset[static_cast<size_t>(i)] + ea))] = find(offset[static_cast<size_t>(j)] + eb);
          any = true;
        }
      }
    }
    if (!any) return;
    for (std::vector<HlrSegment>* list : {&result_.visible, &result_.hidden}) {
      std::vector<HlrSegment> keep;
      std::map<int, std::vector<HlrSegment>> groups;
      for (HlrSegment& s : *list) groups[find(offset[static_cast<size_t>(s.body)] + s.edge)].push_back(s);
      for (auto& [root, segs] : groups) {
        // A group of one edge stays as it is.
        bool single = true;
        for (const HlrSegment& s : segs) single = single && s.body == segs[0].body && s.edge == segs[0].edge;
        if (single) {
          keep.insert(keep.end(), segs.begin(), segs.end());
          continue;
        }
        // Order along the dominant axis of the common line; join overlapping parts.
        int axis;
        (segs[0].b - segs[0].a).cwiseAbs().maxCoeff(&axis);
        for (HlrSegment& s : segs)
          if (s.a[axis] > s.b[axis]) std::swap(s.a, s.b), std::swap(s.a2, s.b2);
        std::sort(segs.begin(), segs.end(), [axis](const HlrSegment& x, const HlrSegment& y) { return x.a[axis] < y.a[axis]; });
        std::vector<HlrSegment> joined{segs[0]};
        for (size_t k = 1; k < segs.size(); ++k) {
          HlrSegment& back = joined.back();
          if (segs[k].a[axis] <= back.b[axis]) {
            if (segs[k].b[axis] > back.b[axis]) back.b = segs[k].b, back.b2 = segs[k].b2;
            if (segs[k].body != back.body || segs[k].edge != back.edge) back.edge = -1;
          } else {
            joined.push_back(segs[k]);
          }
        }
        keep.insert(keep.end(), joined.begin(), joined.end());
      }
      // Keep the list in body/edge order (groups are keyed by root, not by order).
      std::stable_sort(keep.begin(), keep.end(), [](const HlrSegment& x, const HlrSegment& y) {
        return x.body < y.body;
      });
      *list = std::move(keep);
    }
  }

  const std::vector<ExactPlane>& body_planes(int b) {
    BodyData& bd = data_[static_cast<size_t>(b)];
    if (bd.planes.empty())
      for (int f = 0; f < bodies_[static_cast<size_t>(b)].face_count(); ++f)
        bd.planes.push_back(exact_face_plane(bodies_[static_cast<size_t>(b)], f));
    return bd.planes;
  }

  void junctions() {
    const bool brute = options_.stage2 == HlrOptions::Stage2::BruteForce;
    Scratch scratch;
    std::vector<int> ids;
    for (const auto& [pair_i, pair_j] : touching_pairs()) {
      const int i = pair_i, j = pair_j;  // lambdas below capture them (clang 14: not bindings)
      // A junction segment lies on face fa of body i and face fb of body j.
      const detail::CandidateQuery query = [&](const Vec3& a, const Vec3& b, int fa, int fb,
                                               detail::Candidates& out) {
        candidates(a, b, scratch, ids);
        fill_candidates(ids, [&](const PieceData& o) {
          // A convex body's own volume decides exactly (the junction lies exactly on its
          // face's support plane); a piece of a non-convex one only if not incident.
          if (o.body == i) return data_[static_cast<size_t>(i)].convex || !incident(o, fa, fa, a, b);
          if (o.body == j) return data_[static_cast<size_t>(j)].convex || !incident(o, fb, fb, a, b);
          return true;
        }, out);
      };
      int found = 0;
      const std::vector<detail::JunctionPart> parts = detail::junction_lines(
          bodies_[static_cast<size_t>(i)], bodies_[static_cast<size_t>(j)], body_planes(i),
          body_planes(j), view_, query, brute, found);
      result_.stats.junction_segments += found;
      for (const auto& p : parts) add_segment(result_.visible, p.a, p.b, LineKind::Junction, i, j, -1);
    }
  }

  std::span<const Body> bodies_;
  std::span<const std::string> names_;
  Camera camera_;
  HlrOptions options_;
  Viewpoint view_;
  PictureProjection projection_;
  HlrResult result_;
  std::vector<BodyData> data_;
  std::vector<PieceData> pieces_;
  std::vector<FacetData> facets_;
  PictureGrid grid_;
  size_t occluder_count_ = 0;
  std::optional<std::vector<std::pair<int, int>>> pairs_;
  double margin_ = 0, depth_margin_ = 0;
  Eigen::AlignedBox<double, 1> depth_range_;
};

}  // namespace

std::optional<HiddenPart> hidden_part(const OcclusionVolume& volume, const Vec3& p1,
                                      const Vec3& p2) {
  if (!volume.clipper) return std::nullopt;
  const std::optional<Part> part = clip_open(*volume.clipper, p1, p2);
  if (!part) return std::nullopt;
  return HiddenPart{part->lo.t, part->hi.t};
}


HlrResult hidden_lines(std::span<const Body> bodies, const Camera& camera, const HlrOptions& options) {
  camera.validate();
  return Roberts(bodies, {}, camera, options).run();
}

HlrResult hidden_lines(const Scene& scene, const HlrOptions& options) {
  std::vector<Body> bodies;
  std::vector<std::string> names;
  for (const SceneBody* b : scene.visible_bodies()) {
    bodies.push_back(b->body);
    names.push_back(b->name);
  }
  scene.camera.validate();
  return Roberts(bodies, names, scene.camera, options).run();
}

}  // namespace hedra
