// Shadows (docs/algorithms.md §7): self shadows, visible shadows and exact cast-shadow polygons for
// point lights, spot lights, directional lights and the sun, and sun studies over a day.
//
// Method (docs/design.md, "Data flow"). A point X of a face is in the cast shadow of a light
// when the segment (a ray, for a light at infinity) from the light to X meets the interior of
// another convex piece before X, that is when X lies strictly inside the piece's occlusion
// volume as seen from the light (hedra/visibility/occlusion.h); the boundary of a volume is
// lit. The cast shadow on a face is therefore the face polygon clipped against the occlusion
// volumes of every other convex piece, united: each clip is exact in its decisions
// (hedra/core/predicates.h), the union of the clipped convex pieces is computed in the face's
// plane with exact 2D decisions (hedra/visibility/polygon_union.h). Non-convex bodies take part
// through their exact convex pieces (hedra/decompose/decompose.h); convex bodies are never
// decomposed. A uniform grid over the light-space
// projections of the pieces (a bounding-cone test for lights at a finite distance) gives each
// face only the casters whose shadow volumes can reach it.
//
// Self shadows are Roberts' stage 1 with the viewer at the light: a face whose plane has the
// light strictly on its inner side (L·V < 0) is self-shadowed, one whose plane contains the
// light (L·V = 0, a light at infinity parallel to it) is grazing. A self-shadowed face is
// wholly in shadow: its shadow polygons are the face itself and shadow_area == area.
//
// Exactness and error. Every decision (facing, side of a plane, order of crossings, coverage,
// coincident edges) is exact for the double inputs. Only new vertices (edge–plane and
// edge–edge intersections) are rounded, so polygon vertices lie within a few ulps of the
// exact ones and areas have relative errors of order 1e-14 on well-shaped scenes (tests check
// 1e-12 against analytic values and 1e-9 against a CGAL exact union).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hedra/core/progress.h"
#include "hedra/visibility/occlusion.h"
#include "hedra/clip/polygon_clip.h"
#include "hedra/scene/scene.h"
#include "hedra/scene/sun.h"
#include "hedra/visibility/sun_study.h"  // sun studies: declared apart, included here

namespace hedra {

/// A polygon with holes lying on a face's plane. Outer ring counter-clockwise seen from
/// outside the body (the face's own orientation), holes clockwise. Vertices that are not
/// input vertices are rounded intersections (within a few ulps of the face plane).
struct ShadowPolygon {
  Polygon3 outer;
  std::vector<Polygon3> holes;
  double area = 0;  // outer minus holes
};

/// The shadow of one light on one face.
struct FaceShadow {
  int body = 0;     // index into Scene::bodies()
  int face = 0;     // face index of that body
  double area = 0;  // the face's area (Body::face_area)
  /// How the face turns to the light: Back = self-shadowed, EdgeOn = grazing (the light lies
  /// in the face's plane), Front = lit except for cast shadows.
  Facing to_light = Facing::Front;
  /// Front-facing for the scene camera (Facing::Front from Viewpoint::of(camera)).
  bool visible = false;
  /// area when self-shadowed, else the area of the united cast shadows.
  double shadow_area = 0;
  /// The shadowed region (the face itself when self-shadowed), united: disjoint polygons.
  /// Empty when ShadowOptions::polygons is false (shadow_area is still exact).
  std::vector<ShadowPolygon> polygons;
  /// With ShadowOptions::visible_parts: the parts of `polygons` the viewer sees (the face is
  /// front-facing and they are not hidden by other pieces), and their area. Else empty, 0.
  std::vector<ShadowPolygon> visible_polygons;
  double visible_shadow_area = 0;

  bool self_shadowed() const { return to_light == Facing::Back; }
  bool grazing() const { return to_light == Facing::EdgeOn; }
  /// 1 − shadow_area / area, clamped to [0, 1]: the part of the face no other piece shades
  /// (0 for a self-shadowed face; a grazing face gets no direct light whatever this says).
  double lit_fraction() const;
};

/// All faces of all visible bodies for one light.
struct LightShadows {
  Light light;
  /// One entry per face of every visible body, bodies in scene order, faces in body order;
  /// ShadowResult::face() finds the entry of (body, face).
  std::vector<FaceShadow> faces;
};

/// A region of a face shadowed from exactly `count` of the lights (several lights).
struct ShadowCount {
  int body = 0, face = 0;
  int count = 0;  // 1 … lights; count == lights is the umbra, fewer a partial shadow
  double area = 0;
  std::vector<ShadowPolygon> polygons;
};

struct ShadowResult {
  std::vector<LightShadows> lights;  // in the order of the lights computed
  /// With two or more lights and ShadowOptions::counts: for every face shadowed from at least
  /// one light, one entry per count that occurs, ordered by body, face, count.
  std::vector<ShadowCount> counts;
  /// For each body of Scene::bodies(): the index of its face 0 in LightShadows::faces, or −1
  /// for a hidden body.
  std::vector<int> first_face;

  /// The entry of (body, face) for light l. \pre the body is visible, indices in range.
  const FaceShadow& face(int light, int body, int face) const {
    return lights[static_cast<size_t>(light)]
        .faces[static_cast<size_t>(first_face[static_cast<size_t>(body)] + face)];
  }
};

struct ShadowOptions {
  /// Cast shadows (false: self shadows and grazing faces only).
  bool cast = true;
  /// Build the united polygons (false: areas only, a little faster).
  bool polygons = true;
  /// Compute FaceShadow::visible_polygons (the parts the camera sees): costs a second pass of
  /// occlusion volumes from the eye and exact polygon differences.
  bool visible_parts = false;
  /// Compute ShadowResult::counts when there are two or more lights.
  bool counts = true;
  /// Worker threads (0: TBB's default). Results do not depend on it.
  int threads = 0;
  /// How closed non-convex bodies occlude (hedra/visibility/occlusion.h): their exact convex
  /// pieces, or their faces' triangles (Auto: above kFaceOccluderFaces faces).
  Occluders occluders = Occluders::Auto;
  /// Progress and cancellation of the shadow passes (hedra/core/progress.h): the fraction
  /// done, on the calling thread; returning false stops with hedra::Cancelled and no result.
  /// The preparation (decomposing non-convex bodies) is not covered.
  ProgressCallback progress;
};

/// Shadows of every light of the scene on every face of every visible body.
/// Spot lights cast shadows as point lights at their position (the cone limits the lighting,
/// which is the renderer's business, not the shadow). Lights inside a body light nothing
/// outside it: every face of that body turns its back (or edge) to the light.
/// \throw InvalidInput for an invalid light, or when a non-convex body cannot be decomposed.
/// Cost: O(pieces + faces·k) clips with k the casters whose shadow volumes reach a face, plus
/// the unions, O(e·m) for e edges meeting m other shadow pieces.
ShadowResult compute_shadows(const Scene& scene, const ShadowOptions& options = {});

/// Exact test: is point p of face `face` (body `body`, an index into Scene::bodies()) in the
/// self shadow of `light` (the face turns its back to it) or strictly inside the occlusion
/// volume of a convex piece that may shade the face? Independent of the clipping and the
/// union: the check of the sun-study grid and of the tests. Prepares the scene on every call
/// (use ShadowScene for many queries). \pre p on the face (within rounding).
/// \throw InvalidInput for a hidden body, a face out of range or an invalid light.
bool in_shadow(const Scene& scene, const Light& light, int body, int face, const Vec3& p);

/// Point-in-shadow query on computed polygons (for renderers): p is projected along the
/// dominant axis of the polygons' common plane and tested against them (exact orientation
/// tests; inside or on the boundary counts as shadowed, inside a hole does not).
/// Cost O(vertices).
bool point_in_polygons(const std::vector<ShadowPolygon>& polygons, const Vec3& p);

namespace internal {
struct ShadowSceneAccess;
}

/// A scene prepared for shadows: bodies split into convex pieces once, faces into convex
/// parts once, reused for any number of lights (sun studies, animations). Holds a copy of
/// the scene's bodies (shared, immutable geometry).
class ShadowScene {
 public:
  /// \throw InvalidInput when a non-convex body cannot be decomposed.
  explicit ShadowScene(const Scene& scene, Occluders occluders = Occluders::Auto);
  ~ShadowScene();
  ShadowScene(ShadowScene&&) noexcept;
  ShadowScene& operator=(ShadowScene&&) noexcept;

  /// As compute_shadows, for the given lights (camera from the scene given at construction).
  ShadowResult compute(const std::vector<Light>& lights, const ShadowOptions& options = {}) const;
  /// Convex pieces in total (bodies plus the pieces of non-convex bodies).
  int piece_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  friend struct internal::ShadowSceneAccess;  // the shadow and sun-study internals
};

}  // namespace hedra
