#include "hedra/visibility/shadows.h"

#include "hedra/core/progress.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <numeric>

#include "hedra/core/error.h"
#include "hedra/core/parallel.h"
#include "hedra/core/tolerance.h"
#include "hedra/decompose/decompose.h"
#include "hedra/mesh/convexity.h"
#include "visibility/shadows_internal.h"

namespace hedra {

using internal::ShadowBody;
using internal::drop;
using internal::lift_polygon;
using internal::make_face;
using internal::piece_on_face_plane;
using internal::whole_face;
using internal::CasterIndex;
using internal::PieceVolumes;
using internal::ShadowFace;
using internal::ShadowPiece;
using internal::ShadowSceneAccess;
using internal::to_convex_ring;

double FaceShadow::lit_fraction() const {
  if (area <= 0) return 0;
  return std::clamp(1 - shadow_area / area, 0.0, 1.0);
}

void ShadowScene::Impl::hidden_pieces(int b, int f, const CasterIndex& index,
                                      const PieceVolumes& volumes,
                                      std::vector<Ring2>& out) const {
  const ShadowBody& bd = bodies[static_cast<size_t>(b)];
  const ShadowFace& fd = bd.faces[static_cast<size_t>(f)];
  const std::vector<Vec3>& corners = fd.corners;
  thread_local Polygon3 clipped;
  thread_local PolygonClipScratch scratch;
  thread_local Ring2 ring;
  thread_local std::vector<Ring2> part_rings;
  const Viewpoint& view = index.view();
  part_rings.clear();
  bool parts_known = false;
  // A triangle of a faceted body wholly between the viewpoint and the face's plane, whose
  // projection onto that plane lies strictly inside one convex part of the face: the part of
  // the face it hides is that projection. Its corners are projected one by one, so the
  // triangles around a vertex share its projected point exactly and their shadows meet along
  // common edges (a clipped corner is rounded from the clipping chain of each triangle, and
  // thousands of nearly coincident corners sent the union to its exact fallback). The
  // decisions (sides of the plane, inside the part) are exact on the rounded projections.
  const auto project_triangle = [&](const ShadowPiece& piece) {
    // (A face off its plane is clipped on its triangles instead.)
    if (piece.convex || !fd.part_planes.empty()) return false;
    const auto& tv = piece.triangle;
    const Vec3& n = fd.normal;
    const double lit = view.at_infinity ? n.dot(view.direction) : n.dot(fd.anchor - view.point);
    ring.resize(3);
    for (size_t k = 0; k < 3; ++k) {
      // Strictly on the viewpoint's side of the face's plane (its outer side).
      if (side_of_plane(fd.plane, tv[k]) != Sign::Negative) return false;
      Vec3 x;
      if (view.at_infinity) {
        x = tv[k] + (n.dot(fd.anchor - tv[k]) / lit) * view.direction;
      } else {
        const double t = lit / n.dot(tv[k] - view.point);
        if (!(t > 1 + 1e-9) || !std::isfinite(t)) return false;  // not between: clip instead
        x = view.point + t * (tv[k] - view.point);
      }
      ring[k] = drop(x, fd.axis);
    }
    Sign turn = orient2d(ring[0], ring[1], ring[2]);
    if (turn == Sign::Zero) return false;
    if (turn == Sign::Negative) std::swap(ring[1], ring[2]);
    if (!parts_known) {
      fd.for_parts([&](const Polygon3& part) { part_rings.push_back(fd.project(part)); });
      parts_known = true;
    }
    for (const Ring2& part : part_rings) {
      bool inside = true;
      for (size_t i = 0, m = part.size(); i < m && inside; ++i)
        for (const Vec2& q : ring) inside = inside && orient2d(part[i], part[(i + 1) % m], q) == Sign::Positive;
      if (inside) return true;
    }
    return false;
  };
  const bool front = facing(fd.plane, view) == Facing::Front;
  const size_t first = out.size();
  index.candidates(corners, fd.centre, fd.radius, [&](int p) {
    // A convex body never hides its own faces; pieces of a non-convex one may.
    if (pieces[static_cast<size_t>(p)].body == b && bd.skips(f, p, pieces[static_cast<size_t>(p)])) return;
    const ShadowPiece& piece = pieces[static_cast<size_t>(p)];
    if (!piece.convex && front) {
      // A triangle in the closed inner half-space of a face turned to the viewpoint meets
      // the segment from the viewpoint to a point X of the face at X at most: it hides
      // nothing of it (on a tessellated sphere, the neighbours every front face meets).
      bool before = false;
      for (const Vec3& c : piece.triangle) before = before || fd.outside(c);
      if (!before) return;
    }
    if (piece.face >= 0 && project_triangle(piece)) {
      out.push_back(ring);
      return;
    }
    if (!piece.convex) {
      // The first plane of a triangle's volume is its own (open: only its strict inner side is
      // hidden): a face wholly on the other side, or on it, is not hidden. Settles, with the
      // plane the triangle has already, a neighbour across an edge that rounding to float made
      // reflex by an ulp (a sixth of the triangles clipped on a 1M float32 sphere), before a
      // volume is built.
      bool inside = false;
      const ExactPlane& plane = piece.turned_plane(volumes.active[static_cast<size_t>(p)]);
      for (const Vec3& c : corners) inside = inside || side_of_plane(plane, c) == Sign::Positive;
      if (!inside) return;
    }
    const ConvexClipper& clipper = *volumes.volume_of(pieces, p).clipper;
    if (!fd.part_planes.empty()) {
      // Off its plane: each triangle on its own plane, its corners exactly on it.
      for (size_t k = 0; k < fd.parts.size(); ++k)
        if (clip_convex_polygon_open(fd.parts[k], fd.part_planes[k], fd.axis, true, clipper, clipped, scratch) &&
            to_convex_ring(fd, clipped, ring))
          out.push_back(ring);
      return;
    }
    fd.for_parts([&](const Polygon3& part) {
      if (clip_convex_polygon_open(part, fd.plane, fd.axis, fd.planar, clipper, clipped, scratch) &&
          to_convex_ring(fd, clipped, ring))
        out.push_back(ring);
    });
  });
  // Rounding debris (kShadowDebris): a piece thinner than that (mean width 2 · area / perimeter,
  // in the face's 2D frame) is an occlusion volume that only touches the face, an ulp off it
  // (the rounded face of a body whose exact pieces occlude: a hole's wall next to the piece of
  // its neighbour), not a shadow. Dropped before the union, so that a face's shadow_area and
  // its polygons (which drop such rings on output) agree.
  const double snap = kShadowDebris * scale;
  out.erase(std::remove_if(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(),
                           [snap](const Ring2& r) {
                             double perimeter = 0;
                             for (size_t k = 0; k < r.size(); ++k) perimeter += (r[(k + 1) % r.size()] - r[k]).norm();
                             return !(2 * std::abs(ring_area(r)) > snap * perimeter);
                           }),
            out.end());
}

bool ShadowScene::Impl::point_hidden(int b, int f, const Vec3& p, const CasterIndex& index,
                                     const PieceVolumes& volumes) const {
  const ShadowBody& bd = bodies[static_cast<size_t>(b)];
  bool hidden = false;
  index.candidates({p}, p, 0, [&](int q) {
    if (hidden || (pieces[static_cast<size_t>(q)].body == b && bd.skips(f, q, pieces[static_cast<size_t>(q)]))) return;
    hidden = hides(volumes.volume_of(pieces, q), p);
  });
  return hidden;
}

PieceVolumes ShadowScene::Impl::volumes(const Viewpoint& view, int threads) const {
  PieceVolumes v;
  v.view = view;
  v.volumes.resize(static_cast<size_t>(convex_pieces));
  v.active.assign(pieces.size(), 0);
  parallel_for(pieces.size(), threads, [&](size_t p) {
    const ShadowPiece& piece = pieces[p];
    if (!piece.convex) {
      // A triangle of a closed body's face occludes only when the face turns to the viewpoint;
      // a two-sided surface's from either side, reversed from its back.
      v.active[p] = facing(*piece.triangle_plane, view) == Facing::Front ? 1
                    : piece.back_plane && facing(*piece.back_plane, view) == Facing::Front ? 2 : 0;
      return;
    }
    const ShadowPiece::Convex& c = *piece.convex;
    OcclusionVolume& volume = v.volumes[static_cast<size_t>(c.slot)];
    if (c.exact) {
      volume = occlusion_volume(*c.exact, view);
    } else {
      std::vector<Facing> turned(c.planes.size());
      for (size_t f = 0; f < c.planes.size(); ++f) turned[f] = facing(c.planes[f], view);
      volume = occlusion_volume(c.shape, turned, view, c.planes);
    }
    v.active[p] = volume.clipper.has_value();
  });
  return v;
}

ShadowScene::ShadowScene(const Scene& scene, Occluders occluders) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.occluders = occluders;
  m.camera = scene.camera;
  const Eigen::AlignedBox3d box = scene.bbox();
  m.scale = box.isEmpty() ? 1
                          : std::max({box.diagonal().norm(), box.min().cwiseAbs().maxCoeff(),
                                      box.max().cwiseAbs().maxCoeff(), 1e-300});
  m.first_face.assign(scene.bodies().size(), -1);
  int next_face = 0;
  m.bodies.reserve(scene.bodies().size());
  for (size_t s = 0; s < scene.bodies().size(); ++s) {
    const SceneBody& sb = scene.bodies()[s];
    if (sb.hidden) continue;
    ShadowBody bd(sb.body);
    bd.scene_index = static_cast<int>(s);
    bd.name = sb.name;
    m.first_face[s] = next_face;
    next_face += sb.body.face_count();
    m.bodies.push_back(std::move(bd));
  }
  // Convex pieces (decomposing only the non-convex bodies) and face data, in parallel.
  std::vector<std::vector<Body>> pieces(m.bodies.size());
  std::vector<std::vector<std::vector<ExactPlane>>> piece_planes(m.bodies.size());
  std::vector<std::vector<std::vector<std::pair<int, int>>>> exact_planes(m.bodies.size());
  std::vector<std::vector<ExactConvex>> exact_pieces(m.bodies.size());
  parallel_for(m.bodies.size(), 0, [&](size_t b) {
    ShadowBody& bd = m.bodies[b];
    bd.faces.resize(static_cast<size_t>(bd.body.face_count()));
    bd.body.triangles();  // built once, before the faces read it in parallel
    parallel_blocks(bd.faces.size(), 0, 256, [&](size_t begin, size_t end) {
      for (size_t f = begin; f != end; ++f) bd.faces[f] = make_face(bd.body, static_cast<int>(f));
    });
    // A two-sided face is one piece; a two-sided surface occludes by its faces.
    const bool one_face = bd.body.two_sided() && bd.body.face_count() == 2;
    bd.convex = one_face || (!bd.body.two_sided() && is_convex(bd.body));
    if (bd.convex) {
      // The body is its one piece, with its faces' planes (a copy only here: 160 bytes a face);
      // with faces off their planes, the convex polyhedron they bound cut into exactly planar
      // faces, not their support planes, an ulp off it.
      // Its faces in body order, each face off its plane as its triangles in the order of
      // convex_polygon_split: the planes the faces already have (ShadowFace::part_planes).
      std::optional<Body> split;
      if (!bd.body.faces_off_plane().empty()) {
        std::vector<std::vector<std::array<int, 3>>> splits(bd.faces.size());
        for (size_t f = 0; f < bd.faces.size(); ++f) splits[f] = std::move(bd.faces[f].split);
        split = exactly_planar_convex(bd.body, splits);
      }
      std::vector<ExactPlane> planes;
      planes.reserve(split ? static_cast<size_t>(split->face_count()) : bd.faces.size());
      for (const ShadowFace& fd : bd.faces) {
        if (split && !fd.part_planes.empty())
          planes.insert(planes.end(), fd.part_planes.begin(), fd.part_planes.end());
        else
          planes.push_back(fd.plane);
      }
      pieces[b].push_back(split ? std::move(*split) : bd.body);
      piece_planes[b].push_back(std::move(planes));
    } else if (bd.body.two_sided() || occludes_by_faces(bd.body, m.occluders)) {
      // Closed: the faces turned to a viewpoint hide everything the body hides from it
      // (hedra/visibility/occlusion.h, Occluders::Faces).
      // Its pieces are its faces' triangles (face_triangles_of), made below.
      bd.faceted = true;
    } else {
      try {
        DecomposeOptions options;
        options.exact_pieces = true;
        options.prefer_exact_solid = true;  // a moved body: every piece exactly convex
        Decomposition d = decompose(bd.body, options);
        if (m.occluders == Occluders::Auto && !pieces_exactly_convex(d)) {
          bd.faceted = true;  // exact on the body's triangles, not on a rounded piece
          return;
        }
        pieces[b] = std::move(d.pieces);
        exact_planes[b] = std::move(d.piece_planes);
        exact_pieces[b] = std::move(d.exact_pieces);
        bd.input_planes = std::move(d.planes);
      } catch (const InvalidInput& e) {
        throw InvalidInput("body '" + bd.name + "': " + e.what());
      }
      for (const Body& piece : pieces[b]) {
        std::vector<ExactPlane> pp;
        for (int f = 0; f < piece.face_count(); ++f) pp.push_back(exact_face_plane(piece, f));
        piece_planes[b].push_back(std::move(pp));
      }
    }
  });
  // The triangles of the bodies occluding by their faces, kept as corners and one plane each.
  std::vector<std::vector<FaceTriangle>> faceted(m.bodies.size());
  size_t total_pieces = 0;
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    if (m.bodies[b].faceted) {
      // A two-sided surface: its front side's triangles, each occluding from both sides.
      const Body& body = m.bodies[b].body;
      std::vector<char> front;
      if (body.two_sided()) {
        front.assign(static_cast<size_t>(body.face_count()), 0);
        std::fill(front.begin(), front.begin() + body.face_count() / 2, 1);
      }
      faceted[b] = face_triangles_of(body, front);
    }
    total_pieces += pieces[b].size() + faceted[b].size();
  }
  // Every piece default-made first, then filled; a faceted body's triangles in parallel.
  m.pieces.resize(total_pieces);
  const auto place = [](ShadowPiece& pd) {
    Eigen::AlignedBox3d bounds;
    for (const Vec3& p : pd.vertices()) bounds.extend(p);
    pd.centre = bounds.center();
    pd.radius = 0.5 * bounds.diagonal().norm();
  };
  size_t next = 0;
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    ShadowBody& body_data = m.bodies[b];
    body_data.pieces.resize(pieces[b].size() + faceted[b].size());
    std::iota(body_data.pieces.begin(), body_data.pieces.end(), static_cast<int>(next));
    for (size_t k = 0; k < pieces[b].size(); ++k) {
      ShadowPiece& pd = m.pieces[next++];
      pd.convex = std::make_unique<ShadowPiece::Convex>(std::move(pieces[b][k]));
      pd.convex->planes = std::move(piece_planes[b][k]);
      if (k < exact_planes[b].size()) pd.convex->exact_planes = std::move(exact_planes[b][k]);
      if (k < exact_pieces[b].size() && !exact_pieces[b][k].faces.empty())
        pd.convex->exact = std::make_shared<const ExactConvex>(std::move(exact_pieces[b][k]));
      pd.convex->slot = m.convex_pieces++;
      pd.body = static_cast<int>(b);
      place(pd);
    }
    if (faceted[b].empty()) continue;
    const size_t first = next;
    next += faceted[b].size();
    parallel_blocks(faceted[b].size(), 0, 4096, [&](size_t begin, size_t end) {
      for (size_t k = begin; k != end; ++k) {
        ShadowPiece& pd = m.pieces[first + k];
        const int f = faceted[b][k].face;
        pd.triangle = faceted[b][k].corners;
        pd.body = static_cast<int>(b);
        pd.face = f;
        // triangle_plane; for a triangular face listed in its loop's order that is the face's
        // own exact plane, which make_face built already.
        const ShadowFace& fd = body_data.faces[static_cast<size_t>(f)];
        const bool own = body_data.body.faces()[static_cast<size_t>(f)].loops.size() == 1 &&
                         std::equal(fd.corners.begin(), fd.corners.end(), pd.triangle.begin(), pd.triangle.end());
        if (own) {
          pd.triangle_plane = &fd.plane;
        } else {
          pd.own_triangle_plane = std::make_unique<ExactPlane>(triangle_plane(pd.triangle));
          pd.triangle_plane = pd.own_triangle_plane.get();
        }
        if (body_data.body.two_sided()) {
          // The other side: the twin face's plane when the face is this triangle (the same
          // three corners the other way round: the exact plane, negated), else its own.
          const ShadowFace& back = body_data.faces[static_cast<size_t>(body_data.body.twin_face(f))];
          if (own) {
            pd.back_plane = &back.plane;
          } else {
            pd.own_back_plane = std::make_unique<ExactPlane>(triangle_plane(pd.turned(2)));
            pd.back_plane = pd.own_back_plane.get();
          }
        }
        place(pd);
      }
    });
    faceted[b] = {};
  }
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    ShadowBody& bd = m.bodies[b];
    if (!bd.convex && !bd.faceted) {
      bd.own_adjacent.resize(bd.faces.size());
      const double scale = bd.body.scale();
      const InputPlanes& model = bd.input_planes;
      for (size_t f = 0; f < bd.faces.size(); ++f)
        for (int p : bd.pieces) {
          const ShadowPiece& pd = m.pieces[static_cast<size_t>(p)];
          // Exact: the exact piece has a face on one of the face's canonical planes, on the
          // same side (the piece lies on the face's inner side).
          bool on = false;
          const auto& exact = pd.convex->exact_planes;
          if (!model.empty() && !exact.empty()) {
            for (const auto& c : model.face_planes[f])
              on = on || std::binary_search(exact.begin(), exact.end(), c);
          } else {
            on = piece_on_face_plane(pd.convex->shape, bd.faces[f], scale);
          }
          if (on)
            bd.own_adjacent[f].push_back(p);
        }
    }
    for (int f = 0; f < bd.body.face_count(); ++f) m.faces.emplace_back(static_cast<int>(b), f);
  }
}

ShadowScene::~ShadowScene() = default;
ShadowScene::ShadowScene(ShadowScene&&) noexcept = default;
ShadowScene& ShadowScene::operator=(ShadowScene&&) noexcept = default;

int ShadowScene::piece_count() const { return static_cast<int>(impl_->pieces.size()); }

namespace {

// A region kept for a face as polygons with holes: the union unite_convex chained, or where none
// was kept (the face wholly shadowed) the union of the pieces, here the face's convex parts.
std::vector<PolygonWithHoles2> region_of(const std::vector<PolygonWithHoles2>& united,
                                         const std::vector<Ring2>& pieces) {
  if (!united.empty() || pieces.empty()) return united;
  return unite_convex(pieces, true).polygons;
}

}  // namespace

ShadowResult ShadowScene::compute(const std::vector<Light>& lights,
                                  const ShadowOptions& options) const {
  const Impl& m = *impl_;
  ShadowResult result;
  result.first_face = m.first_face;
  const size_t nf = m.faces.size();
  const bool keep_pieces =
      options.polygons && (options.visible_parts || (options.counts && lights.size() >= 2));
  // 2D shadow pieces per light and face, kept for the visible parts and the counts, and their
  // union as unite_convex chained it (empty where the face is wholly shadowed: its parts then).
  std::vector<std::vector<std::vector<Ring2>>> kept(lights.size());
  std::vector<std::vector<std::vector<PolygonWithHoles2>>> kept_union(lights.size());
  // ShadowOptions::progress: the lights' passes share the first 80 %, the visible parts and the
  // counts the rest; units are faces.
  ProgressMeter meter(options.progress, "shadows cancelled");
  const double passes = static_cast<double>(lights.size());

  for (size_t l = 0; l < lights.size(); ++l) {
    lights[l].validate();
    const Viewpoint view = Viewpoint::of(lights[l]);
    const Viewpoint eye = Viewpoint::of(m.camera);
    LightShadows ls;
    ls.light = lights[l];
    ls.faces.resize(nf);
    PieceVolumes volumes;
    std::optional<CasterIndex> index;
    if (options.cast) {
      volumes = m.volumes(view, options.threads);
      index.emplace(m.pieces, volumes, view, m.scale, options.threads);
    }
    if (keep_pieces) {
      kept[l].resize(nf);
      kept_union[l].resize(nf);
    }
    meter.stage(0.8 * l / passes, 0.8 * (l + 1) / passes, static_cast<double>(nf));
    parallel_for(nf, options.threads, [&](size_t i) {
      meter.add();
      const auto [b, f] = m.faces[i];
      const ShadowBody& bd = m.bodies[static_cast<size_t>(b)];
      const ShadowFace& fd = bd.faces[static_cast<size_t>(f)];
      FaceShadow& fs = ls.faces[i];
      fs.body = bd.scene_index;
      fs.face = f;
      fs.area = fd.area;
      fs.to_light = facing(fd.plane, view);
      fs.visible = facing(fd.plane, eye) == Facing::Front;
      if (fs.to_light == Facing::Back) {
        fs.shadow_area = fs.area;
        if (options.polygons) fs.polygons.push_back(whole_face(bd.body, f));
        if (keep_pieces) kept[l][i] = fd.parts2d();
        return;
      }
      if (!options.cast) return;
      std::vector<Ring2> rings;
      m.hidden_pieces(b, f, *index, volumes, rings);
      if (rings.empty()) return;
      const UnionResult u = unite_convex(rings, options.polygons);
      fs.shadow_area = std::min(u.area * fd.area_factor, fs.area);
      for (const PolygonWithHoles2& p : u.polygons) lift_polygon(fd, p, m.scale, fs.polygons);
      if (keep_pieces) {
        kept[l][i] = std::move(rings);
        kept_union[l][i] = u.polygons;
      }
    });
    meter.finish_stage();
    result.lights.push_back(std::move(ls));
  }

  // Visible parts: the shadow minus what other pieces hide from the eye.
  if (options.polygons && options.visible_parts && !lights.empty()) {
    const Viewpoint eye = Viewpoint::of(m.camera);
    const PieceVolumes eye_volumes = m.volumes(eye, options.threads);
    const CasterIndex eye_index(m.pieces, eye_volumes, eye, m.scale, options.threads);
    meter.stage(0.8, 0.9, static_cast<double>(nf));
    parallel_for(nf, options.threads, [&](size_t i) {
      meter.add();
      const auto [b, f] = m.faces[i];
      const ShadowFace& fd = m.bodies[static_cast<size_t>(b)].faces[static_cast<size_t>(f)];
      bool any = false;
      for (size_t l = 0; l < lights.size(); ++l) any = any || !kept[l][i].empty();
      if (!any || !result.lights[0].faces[i].visible) return;
      std::vector<Ring2> hidden;
      m.hidden_pieces(b, f, eye_index, eye_volumes, hidden);
      // The difference of the two unions, not of their pieces: on a large face of a mesh scene
      // both are hundreds of thousands of pieces and their unions a few thousand vertices.
      std::vector<Region2> hidden_union(1);
      if (!hidden.empty()) hidden_union[0] = unite_convex(hidden, true).polygons;
      for (size_t l = 0; l < lights.size(); ++l) {
        FaceShadow& fs = result.lights[l].faces[i];
        if (kept[l][i].empty()) continue;
        if (hidden.empty()) {
          fs.visible_polygons = fs.polygons;
          fs.visible_shadow_area = fs.shadow_area;
          continue;
        }
        std::optional<UnionResult> v =
            cgal_difference(region_of(kept_union[l][i], kept[l][i]), hidden_union);
        if (!v) v = cgal_difference(kept[l][i], hidden);
        for (const PolygonWithHoles2& p : v->polygons)
          lift_polygon(fd, p, m.scale, fs.visible_polygons);
        fs.visible_shadow_area = v->area * fd.area_factor;
      }
    });
    meter.finish_stage();
  }

  // Several lights: regions by the number of lights they are shadowed from.
  if (options.polygons && options.counts && lights.size() >= 2) {
    std::vector<std::vector<ShadowCount>> per_face(nf);
    meter.stage(0.9, 1.0, static_cast<double>(nf));
    parallel_for(nf, options.threads, [&](size_t i) {
      meter.add();
      // Plain variables, not a structured binding: the lambdas below capture f (clang 14, the
      // fuzz and sanitizer compiler, cannot capture bindings).
      const auto [face_body, face_index] = m.faces[i];
      const auto b = face_body, f = face_index;
      const ShadowBody& bd = m.bodies[static_cast<size_t>(b)];
      const ShadowFace& fd = bd.faces[static_cast<size_t>(f)];
      // A light the face turns its back to shadows all of it: it adds one to every count.
      // Only the lights with cast shadows need Boolean operations.
      int whole = 0;
      std::vector<size_t> partial;
      for (size_t l = 0; l < lights.size(); ++l) {
        if (result.lights[l].faces[i].to_light == Facing::Back)
          ++whole;
        else if (!kept[l][i].empty())
          partial.push_back(l);
      }
      if (whole == 0 && partial.empty()) return;
      auto add = [&](int count, double area, std::vector<ShadowPolygon> polys) {
        per_face[i].push_back({bd.scene_index, f, count, area, std::move(polys)});
      };
      auto lifted = [&](const UnionResult& u) {
        std::vector<ShadowPolygon> polys;
        for (const PolygonWithHoles2& p : u.polygons) lift_polygon(fd, p, m.scale, polys);
        return polys;
      };
      if (partial.empty()) {
        add(whole, fd.area, {whole_face(bd.body, f)});
        return;
      }
      // The face outside every cast shadow keeps the count of the wholly shadowing lights.
      std::vector<Region2> regions;  // each partially shadowing light's shadow
      for (size_t l : partial) regions.push_back(region_of(kept_union[l][i], kept[l][i]));
      if (whole > 0) {
        std::optional<UnionResult> rest =
            cgal_difference(unite_convex(fd.parts2d(), true).polygons, regions);
        if (!rest) {
          std::vector<Ring2> all;
          for (size_t l : partial) all.insert(all.end(), kept[l][i].begin(), kept[l][i].end());
          rest = cgal_difference(fd.parts2d(), all);
        }
        if (!rest->polygons.empty()) add(whole, rest->area * fd.area_factor, lifted(*rest));
      }
      if (partial.size() == 1) {
        const FaceShadow& fs = result.lights[partial[0]].faces[i];
        add(whole + 1, fs.shadow_area, fs.polygons);
        return;
      }
      std::optional<std::vector<UnionResult>> by_regions = cgal_coverage_levels(regions);
      if (!by_regions) {
        std::vector<std::vector<Ring2>> sets;
        for (size_t l : partial) sets.push_back(kept[l][i]);
        by_regions = cgal_coverage_levels(sets);
      }
      const std::vector<UnionResult>& levels = *by_regions;
      for (size_t k = 0; k < levels.size(); ++k)
        if (!levels[k].polygons.empty())
          add(whole + static_cast<int>(k + 1), levels[k].area * fd.area_factor, lifted(levels[k]));
    });
    meter.finish_stage();
    for (auto& v : per_face)
      for (ShadowCount& c : v) result.counts.push_back(std::move(c));
  }
  meter.stage(1, 1, 1);
  meter.finish_stage();  // the last report is 1
  return result;
}

ShadowResult compute_shadows(const Scene& scene, const ShadowOptions& options) {
  return ShadowScene(scene, options.occluders).compute(scene.lights, options);
}

bool in_shadow(const Scene& scene, const Light& light, int body, int face, const Vec3& p) {
  const SceneBody& sb = scene.bodies().at(static_cast<size_t>(body));
  if (sb.hidden || face < 0 || face >= sb.body.face_count())
    throw InvalidInput("in_shadow: no such face of a visible body");
  light.validate();
  const ShadowScene prepared(scene);
  const auto& m = ShadowSceneAccess::impl(prepared);
  int b = 0;
  while (m.bodies[static_cast<size_t>(b)].scene_index != body) ++b;
  const Viewpoint view = Viewpoint::of(light);
  if (facing(m.bodies[static_cast<size_t>(b)].faces[static_cast<size_t>(face)].plane, view) ==
      Facing::Back)
    return true;
  const PieceVolumes volumes = m.volumes(view, 1);
  const CasterIndex index(m.pieces, volumes, view, m.scale);
  return m.point_hidden(b, face, p, index, volumes);
}

bool point_in_polygons(const std::vector<ShadowPolygon>& polygons, const Vec3& p) {
  // One projection for all: the polygons lie on one plane and share the orientation of their
  // outer rings, so the sum of their Newell vectors is the plane's normal (a sliver alone
  // could point anywhere).
  Vec3 n = Vec3::Zero();
  for (const ShadowPolygon& poly : polygons) n += polygon_normal(poly.outer);
  int k;
  n.cwiseAbs().maxCoeff(&k);
  for (const ShadowPolygon& poly : polygons) {
    auto inside = [&](const Polygon3& ring, bool& on) {
      const Vec2 q = drop(p, k);
      bool in = false;
      on = false;
      for (size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
        const Vec2 a = drop(ring[i], k), b = drop(ring[j], k);
        if (orient2d(a, b, q) == Sign::Zero && q.x() >= std::min(a.x(), b.x()) &&
            q.x() <= std::max(a.x(), b.x()) && q.y() >= std::min(a.y(), b.y()) &&
            q.y() <= std::max(a.y(), b.y())) {
          on = true;
          return true;
        }
        if ((a.y() > q.y()) != (b.y() > q.y())) {
          // Crossing of the horizontal ray to the right: decided by orientation.
          const Sign s = orient2d(a, b, q);
          if ((b.y() > a.y()) == (s == Sign::Negative)) in = !in;
        }
      }
      return in;
    };
    bool on = false;
    if (!inside(poly.outer, on)) continue;
    if (on) return true;
    bool in_hole = false;
    for (const Polygon3& h : poly.holes) {
      bool on_hole = false;
      if (inside(h, on_hole) && !on_hole) in_hole = true;
    }
    if (!in_hole) return true;
  }
  return false;
}

}  // namespace hedra
