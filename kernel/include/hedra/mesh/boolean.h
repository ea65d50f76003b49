// Boolean operations on bodies (closed solids in, closed solid out).
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include "hedra/core/body.h"

namespace hedra {

/// A ∪ B, A − B, A ∩ B through CGAL's Polygon_mesh_processing corefinement on an
/// exact-constructions kernel (Epeck). The exact result's coplanar triangles are merged into
/// polygonal faces by exact plane comparison before coordinates are rounded to double, so a
/// box minus a box stays a body with planar polygonal faces. The result keeps the exact
/// solid it rounds (Body::has_exact_solid()): a Boolean of results, nested to any depth, and
/// their affine moves, are computed from the exact solids, so volume identities hold exactly
/// (exact_volume_sign()); only the bodies handed out are rounded. Coplanar and touching inputs are
/// handled (a box subtracted from a box sharing a face; boxes touching along an edge).
/// An empty result (A ⊆ B for subtract, disjoint or only touching for intersect) is nullopt.
/// \throw InvalidInput when the result is not a 2-manifold solid (the union of two boxes
///   touching only along an edge) — hedra bodies are manifold.
/// Cost: O((n + k) log(n + k)) exact operations, n input triangles, k intersections.
Body unite(const Body& a, const Body& b);
std::optional<Body> subtract(const Body& a, const Body& b);
std::optional<Body> intersect(const Body& a, const Body& b);

/// The sign of Σ k·V(body) over `terms`, exactly: each body's volume from its exact solid
/// where it keeps one (a Boolean's result), else from its triangles with their double
/// corners. For volume identities: {{1, A − B}, {1, A ∩ B}, {−1, A}} gives Zero.
/// Cost O(T) exact operations for T triangles in all.
Sign exact_volume_sign(const std::vector<std::pair<int, Body>>& terms);

/// Intersection of two convex bodies directly from their body matrices: the convex polyhedron
/// of the union of their plane sets (vertex enumeration and hull in exact arithmetic, from the
/// planes' double coefficients). Same result as intersect() for convex inputs.
/// \pre both bodies convex. nullopt when the intersection has no interior.
/// Cost O(n⁴) for n planes in all (meant for bodies of tens of faces).
std::optional<Body> intersect_convex(const Body& a, const Body& b);

}  // namespace hedra
