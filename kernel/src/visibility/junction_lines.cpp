// Hidden lines, the junction lines (hedra/visibility/roberts.h, stage 3): edges of different
// bodies on one line joined, and the visible parts of the lines where bodies meet (the exact
// penetration points are computed in roberts_exact.cpp).
#include <algorithm>
#include <functional>
#include <map>
#include <numeric>
#include <optional>

#include "hedra/core/error.h"
#include "hedra/core/parallel.h"
#include "visibility/roberts_internal.h"

namespace hedra::internal {

const std::vector<std::pair<int, int>>& Roberts::touching_pairs() {
  if (!pairs_) pairs_ = find_touching_pairs();
  return *pairs_;
}

// The pairs of bodies whose closed bounding boxes meet: each box against the boxes sharing a
// cell of a grid over the ground plane (PictureGrid: cells about the boxes' mean size), later
// indices only, once each. O(n) for boxes of similar size spread over the plane, plus the
// cells a large box covers; boxes stacked over one cell (a tower) meet all of each other, as
// in any sweep. A sweep along x alone was O(n^1.5) on a grid of boxes (each box
// against its whole column), and CGAL's box_intersection_d slower still on boxes sharing one
// z range (0.72 against 0.26 ms for 1 600 boxes).
std::vector<std::pair<int, int>> Roberts::find_touching_pairs() const {
  const size_t n = bodies_.size();
  std::vector<std::pair<int, int>> out;
  if (!options_.spatial_index || options_.stage2 == HlrOptions::Stage2::BruteForce) {
    // The reference: every pair, O(n²).
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i + 1; j < n; ++j)
        if (bodies_[i].bbox().intersects(bodies_[j].bbox())) out.emplace_back(static_cast<int>(i), static_cast<int>(j));
    return out;
  }
  std::vector<Eigen::AlignedBox2d> ground(n);
  Eigen::AlignedBox2d extent;
  extent.setEmpty();
  for (size_t b = 0; b < n; ++b) {
    const Eigen::AlignedBox3d& box = bodies_[b].bbox();
    ground[b] = Eigen::AlignedBox2d(box.min().head<2>(), box.max().head<2>());
    extent.extend(ground[b]);
  }
  PictureGrid grid;
  grid.build(ground, extent);
  std::vector<size_t> seen(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::AlignedBox3d& box = bodies_[i].bbox();
    grid.visit(ground[i], [&](int id) {
      const size_t j = static_cast<size_t>(id);
      if (j <= i || seen[j] == i + 1) return;
      seen[j] = i + 1;
      if (box.intersects(bodies_[j].bbox())) out.emplace_back(static_cast<int>(i), id);
    });
  }
  std::sort(out.begin(), out.end());
  return out;
}

void Roberts::build_grids() {
  if (!grids_.empty()) return;
  grids_.resize(bodies_.size());
  std::vector<int> partners(bodies_.size(), 0);
  for (const auto& [i, j] : touching_pairs()) ++partners[static_cast<size_t>(i)], ++partners[static_cast<size_t>(j)];
  parallel_blocks(bodies_.size(), threads_, 1, [&](size_t begin, size_t end) {
    for (size_t b = begin; b != end; ++b) {
      const Body& body = bodies_[b];
      if (partners[b] < kGridPartners || body.face_count() <= kGridFaces) continue;
      auto grid = std::make_unique<BodyGrid>();
      // The two widest axes of the body's box.
      const Vec3 size = body.bbox().sizes();
      int thin = 0;
      for (int k = 1; k < 3; ++k)
        if (size[k] < size[thin]) thin = k;
      grid->u = (thin + 1) % 3;
      grid->v = (thin + 2) % 3;
      const Eigen::AlignedBox2d extent = grid->flat(body.bbox());
      std::vector<Eigen::AlignedBox2d> boxes(static_cast<size_t>(body.face_count()));
      for (int f = 0; f < body.face_count(); ++f) boxes[static_cast<size_t>(f)] = grid->flat(detail::face_box(body, f));
      grid->faces.build(boxes, extent);
      const auto& v = body.vertices();
      boxes.resize(static_cast<size_t>(body.edge_count()));
      for (int e = 0; e < body.edge_count(); ++e) {
        const Edge& edge = body.edges()[static_cast<size_t>(e)];
        const Vec3 &p = v[static_cast<size_t>(edge.v0)], &q = v[static_cast<size_t>(edge.v1)];
        boxes[static_cast<size_t>(e)] = grid->flat(Eigen::AlignedBox3d(p.cwiseMin(q), p.cwiseMax(q)));
      }
      grid->edges.build(boxes, extent);
      grids_[b] = std::move(grid);
    }
  });
}

namespace {

template <class Visit>
std::vector<int> listed_once(Visit visit) {
  std::vector<int> out;
  visit([&](int id) { out.push_back(id); });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

std::vector<int> Roberts::grid_faces(int b, const Eigen::AlignedBox3d& box) const {
  const BodyGrid& g = *grids_[static_cast<size_t>(b)];
  return listed_once([&](const auto& f) { g.faces.visit(g.flat(box), f); });
}

std::vector<int> Roberts::grid_edges(int b, const Eigen::AlignedBox3d& box) const {
  const BodyGrid& g = *grids_[static_cast<size_t>(b)];
  return listed_once([&](const auto& f) { g.edges.visit(g.flat(box), f); });
}

void Roberts::merge_coincident() {
  const auto& pairs = touching_pairs();
  if (pairs.empty()) return;
  build_grids();
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
  std::vector<int> all_b, listed_a;
  for (const auto& [pi, pj] : pairs) {
    // The body of fewer edges outside, so that a body with a grid is the inner one and only its
    // edges near each outer edge are read.
    const bool swap = bodies_[static_cast<size_t>(pi)].edge_count() > bodies_[static_cast<size_t>(pj)].edge_count();
    const int i = swap ? pj : pi, j = swap ? pi : pj;
    const Body &a = bodies_[static_cast<size_t>(i)], &b = bodies_[static_cast<size_t>(j)];
    const BodyGrid* grid_a = grids_[static_cast<size_t>(i)].get();
    const BodyGrid* grid_b = grids_[static_cast<size_t>(j)].get();
    if (grid_a) listed_a = grid_edges(i, b.bbox());
    const int count_a = grid_a ? static_cast<int>(listed_a.size()) : a.edge_count();
    if (!grid_b) {
      all_b.resize(static_cast<size_t>(b.edge_count()));
      std::iota(all_b.begin(), all_b.end(), 0);
    }
    for (int k = 0; k < count_a; ++k) {
      const int ea = grid_a ? listed_a[static_cast<size_t>(k)] : k;
      const Edge& x = a.edges()[static_cast<size_t>(ea)];
      const Vec3 &a0 = a.vertices()[static_cast<size_t>(x.v0)], &a1 = a.vertices()[static_cast<size_t>(x.v1)];
      const Eigen::AlignedBox3d box_a(a0.cwiseMin(a1), a0.cwiseMax(a1));
      if (!box_a.intersects(b.bbox())) continue;
      const std::vector<int> near_b = grid_b ? grid_edges(j, box_a) : std::vector<int>();
      for (const int eb : grid_b ? near_b : all_b) {
        const Edge& y = b.edges()[static_cast<size_t>(eb)];
        const Vec3 &b0 = b.vertices()[static_cast<size_t>(y.v0)], &b1 = b.vertices()[static_cast<size_t>(y.v1)];
        if (!box_a.intersects(Eigen::AlignedBox3d(b0.cwiseMin(b1), b0.cwiseMax(b1)))) continue;
        // An end of the edge is on its line without the predicate (whose filter cannot settle a
        // repeated point: exact arithmetic, for every edge faces of an open surface share).
        const auto on_line = [&](const Vec3& p) { return p == a0 || p == a1 || collinear(a0, a1, p); };
        if (!on_line(b0) || !on_line(b1)) continue;
        // Joined in the pair's order (the first body's edge under the second's), as before the
        // grid: the groups do not depend on which body ran outside.
        const int e_first = swap ? eb : ea, e_second = swap ? ea : eb;
        parent[static_cast<size_t>(find(offset[static_cast<size_t>(pi)] + e_first))] = find(offset[static_cast<size_t>(pj)] + e_second);
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

const ExactPlane& Roberts::built_face_plane(int b, int f) const {
  const HlrBody& bd = data_[static_cast<size_t>(b)];
  const int slot = bd.plane_slot.empty() ? -1 : bd.plane_slot[static_cast<size_t>(f)];
  HEDRA_ASSERT(slot >= 0, "junction lines: a face plane that junctions() did not build");
  return (*bd.planes)[static_cast<size_t>(slot)];
}

const ExactPlane& Roberts::face_plane(int b, int f) {
  HlrBody& bd = data_[static_cast<size_t>(b)];
  if (bd.plane_slot.empty()) bd.plane_slot.assign(static_cast<size_t>(bodies_[static_cast<size_t>(b)].face_count()), -1);
  int& slot = bd.plane_slot[static_cast<size_t>(f)];
  if (slot < 0) {
    if (!bd.planes) bd.planes = std::make_unique<std::deque<ExactPlane>>();
    slot = static_cast<int>(bd.planes->size());
    bd.planes->push_back(exact_face_plane(bodies_[static_cast<size_t>(b)], f));
  }
  return (*bd.planes)[static_cast<size_t>(slot)];
}

namespace {

// Whether the two-sided faces a and b may cross along a junction line. Not when one lies on one
// closed side of the other's plane: a ∩ b then lies on an edge or vertex of one of them, which
// is drawn as that face's edge. Not when they share a corner (neighbours on one surface): two
// faces of a surface that does not pass through itself meet only in their common edge or
// corner, drawn already (a surface that does pass through itself at a shared corner gets no
// junction line there). This settles the faces of an open surface against their neighbours
// (about 12 per triangle of a mesh) in a few comparisons and exact orientations each, instead
// of the exact junction construction. Cost O(|a|·|b|).
bool two_sided_faces_cross(const Body& a, const Body& b) {
  for (const Vec3& p : a.vertices())
    for (const Vec3& q : b.vertices())
      if (p == q) return false;
  const auto separates = [](const Body& x, const Body& y) {
    const auto& s = x.support(0);
    const auto& v = x.vertices();
    const Vec3 &p = v[static_cast<size_t>(s[0])], &q = v[static_cast<size_t>(s[1])], &r = v[static_cast<size_t>(s[2])];
    bool pos = false, neg = false;
    for (const Vec3& w : y.vertices()) {
      const Sign side = orient3d(p, q, r, w);
      pos = pos || side == Sign::Positive;
      neg = neg || side == Sign::Negative;
      if (pos && neg) return true;
    }
    return false;
  };
  return separates(a, b) && separates(b, a);
}

}  // namespace

void Roberts::junctions() {
  // Pairs of bodies whose boxes meet, less the pairs of two-sided faces that do not cross.
  std::vector<std::pair<int, int>> pairs = touching_pairs();
  {
    std::vector<char> keep(pairs.size(), 1);
    parallel_chunks(pairs.size(), 4096, [&](size_t, size_t begin, size_t end) {
      for (size_t k = begin; k != end; ++k) {
        const Body &a = bodies_[static_cast<size_t>(pairs[k].first)], &b = bodies_[static_cast<size_t>(pairs[k].second)];
        // Two-sided faces, one each (a surface of many faces is one body, faceted).
        const bool faces = a.two_sided() && b.two_sided() && a.face_count() == 2 && b.face_count() == 2;
        keep[k] = !faces || two_sided_faces_cross(a, b);
      }
    });
    size_t n = 0;
    for (size_t k = 0; k < pairs.size(); ++k)
      if (keep[k]) pairs[n++] = pairs[k];
    pairs.resize(n);
  }
  if (pairs.empty()) return;
  const bool brute = options_.stage2 == HlrOptions::Stage2::BruteForce;
  // Faces facing strictly away of each convex body: junctions on them are hidden by the body.
  std::vector<std::vector<bool>> back(bodies_.size());
  for (size_t b = 0; b < bodies_.size(); ++b) {
    // A faceted body is closed too: a face turned away lies behind the faces turned to the eye.
    if (!data_[b].convex && !data_[b].faceted) continue;
    back[b].resize(data_[b].facing.size());
    for (size_t f = 0; f < back[b].size(); ++f) back[b][f] = data_[b].facing[f] == Facing::Back;
  }
  // The face planes junction_lines reads, built here: face_plane builds them on demand, and
  // the pairs below run in parallel (each pair's segments in its own list, joined in pair
  // order: the result does not depend on the threads). It reads the plane of a face only when
  // the face's box meets the other body's box, so only those are built: a sphere resting on a
  // slab needs the few faces at the contact, not its 74 000 (10 % of hidden lines, in 160-byte
  // planes). A body in more than 8 pairs tests its faces against the box of all its partners.
  std::vector<std::vector<int>> partners(bodies_.size());
  for (const auto& [i, j] : pairs) {
    partners[static_cast<size_t>(i)].push_back(j);
    partners[static_cast<size_t>(j)].push_back(i);
  }
  build_grids();
  for (size_t b = 0; b < bodies_.size(); ++b) {
    if (partners[b].empty()) continue;
    if (grids_[b]) {
      // Its faces near each partner, from its grid (not the box of all partners: buildings
      // spread over a terrain cover all of it).
      std::vector<char> meets(static_cast<size_t>(bodies_[b].face_count()), 0);
      for (int o : partners[b])
        for (int f : grid_faces(static_cast<int>(b), bodies_[static_cast<size_t>(o)].bbox()))
          if (!meets[static_cast<size_t>(f)] && detail::face_box(bodies_[b], f).intersects(bodies_[static_cast<size_t>(o)].bbox())) {
            meets[static_cast<size_t>(f)] = 1;
            face_plane(static_cast<int>(b), f);
          }
      continue;
    }
    std::vector<Eigen::AlignedBox3d> near;
    for (int o : partners[b]) near.push_back(bodies_[static_cast<size_t>(o)].bbox());
    if (near.size() > 8) {
      for (size_t k = 1; k < near.size(); ++k) near[0].extend(near[k]);
      near.resize(1);
    }
    const Body& body = bodies_[b];
    const std::vector<char> meets = detail::faces_meeting(body, near);
    for (int f = 0; f < body.face_count(); ++f)
      if (meets[static_cast<size_t>(f)]) face_plane(static_cast<int>(b), f);
  }
  std::vector<std::vector<HlrSegment>> out(pairs.size());
  std::vector<int> found(pairs.size(), 0);
  parallel_blocks(pairs.size(), threads_, 4, [&](size_t begin, size_t end) {
    Scratch scratch;
    std::vector<int> ids;
    detail::ExactPlaneCache cache;
    for (size_t k = begin; k != end; ++k) {
      // Plain variables, not a structured binding: the lambdas below capture them (clang 14,
      // the fuzz and sanitizer compiler, cannot capture bindings).
      const int i = pairs[k].first, j = pairs[k].second;
      meter_.add();  // HlrOptions::progress
      // A junction segment lies on face fa of body i and face fb of body j.
      const detail::CandidateQuery query = [&](const Vec3& a, const Vec3& b, int fa, int fb,
                                               detail::Candidates& candidates_out) {
        candidates(a, b, scratch, ids);
        // Nearest first: a piece that hides the whole segment ends its test.
        near_first(ids, scratch);
        fill_candidates(ids, [&](const HlrPiece& o) {
          // A convex body never hides a point of its own boundary that is not on a face turned
          // away (those were settled above, hidden_by_own): the way to the eye leaves the body
          // at once. So its volume is no candidate. (Testing it would rely on the junction lying
          // exactly on the face's support plane, which a face planar only within --tolerance
          // does not give: issue 14, a cylinder standing on a ground lost its contact line.)
          // A piece of a non-convex body only if not incident; a triangle of a faceted body:
          // any but those of the junction's own face.
          if (o.face >= 0 && o.body == i) return o.face != fa;
          if (o.face >= 0 && o.body == j) return o.face != fb;
          if (o.body == i) return !data_[static_cast<size_t>(i)].convex && !face_incident(o, fa, a, b);
          if (o.body == j) return !data_[static_cast<size_t>(j)].convex && !face_incident(o, fb, a, b);
          return true;
        }, candidates_out);
      };
      // A body with a grid: its faces near the other body's box (a superset), not all of them.
      std::optional<std::vector<int>> near_i, near_j;
      if (grids_[static_cast<size_t>(i)]) near_i = grid_faces(i, bodies_[static_cast<size_t>(j)].bbox());
      if (grids_[static_cast<size_t>(j)]) near_j = grid_faces(j, bodies_[static_cast<size_t>(i)].bbox());
      const std::vector<detail::JunctionPart> parts = detail::junction_lines(
          bodies_[static_cast<size_t>(i)], bodies_[static_cast<size_t>(j)],
          [&](int f) -> const ExactPlane& { return built_face_plane(i, f); },
          [&](int f) -> const ExactPlane& { return built_face_plane(j, f); }, view_, query, brute, found[k],
          back[static_cast<size_t>(i)], back[static_cast<size_t>(j)], &cache, near_i ? &*near_i : nullptr,
          near_j ? &*near_j : nullptr);
      for (const auto& p : parts) add_segment(out[k], p.a, p.b, LineKind::Junction, i, j, -1);
    }
  });
  for (size_t k = 0; k < pairs.size(); ++k) {
    result_.stats.junction_segments += found[k];
    result_.visible.insert(result_.visible.end(), out[k].begin(), out[k].end());
  }
}

}  // namespace hedra::internal
