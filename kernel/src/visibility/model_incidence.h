// Incidence of input vertices with the planes of a rounded decomposition piece's occlusion
// volume, decided in the decomposition's exact model (docs/design.md, "Exact incidence of
// pieces"): hidden lines' ends of hidden parts (Roberts::end_snapped).
#pragma once

#include <utility>
#include <vector>

#include "hedra/core/body.h"
#include "hedra/decompose/decompose.h"
#include "hedra/visibility/occlusion.h"

namespace hedra::internal {

/// Per face of a rounded decomposition piece: the canonical plane (InputPlanes) of the exact
/// piece's face it rounds, or −1. `exact_faces` are the exact piece's (plane, sign) pairs
/// (Decomposition::piece_planes). A face is matched to the canonical plane whose oriented normal
/// its own matches within 1e-10 (rounding turns a face's normal by about an ulp of the
/// coordinates over the face's size), kept only when no other face of the exact piece comes
/// within 1e-8; the faces of the convex-hull fallback and slivers whose rounded normal is off
/// stay −1. Cost O(F·P) for F faces and P exact faces.
std::vector<int> rounded_face_planes(const Body& piece,
                                     const std::vector<std::pair<int, int>>& exact_faces,
                                     const InputPlanes& model);

/// Whether the exact counterpart of plane i of `volume` (the occlusion volume of the rounded
/// `piece`, planes in occlusion_volume's order) passes through input vertex w at q in the
/// model: a front face's plane stands for its canonical plane, which must hold w
/// (InputPlanes::on); a silhouette edge's plane (through the edge's rounded corners, its two
/// first points) for the plane through the line where the canonical planes of the edge's two
/// faces meet and the viewpoint, which holds w when both of them do. False when a plane is
/// unknown (−1 in `face_planes`). Cost O(1) for a front plane, O(E) for a silhouette plane.
bool volume_plane_through(const OcclusionVolume& volume, size_t i, const Body& piece,
                          const std::vector<int>& face_planes, const InputPlanes& model, int w,
                          const Vec3& q);

/// The same for the occlusion volume of an exact piece (occlusion_volume(const ExactConvex&,
/// …): its front faces' planes, then a plane per edge between a front face and one that is
/// not, in edge order): a front plane passes through w when its face's canonical plane
/// (ExactConvex::canonical) holds w, an edge's plane (the pencil through the edge and the
/// viewpoint, or the other face's plane when that face is edge-on) when the canonical planes
/// of both faces do. False where a face has none. Cost O(1) for a front plane, O(E) for an
/// edge's.
bool exact_volume_plane_through(const OcclusionVolume& volume, size_t i, const ExactConvex& piece,
                                const InputPlanes& model, int w, const Vec3& q);

}  // namespace hedra::internal
