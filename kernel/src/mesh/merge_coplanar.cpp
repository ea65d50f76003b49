#include "hedra/mesh/merge_coplanar.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <numeric>
#include <span>

#include <Eigen/SVD>
#include <string>
#include <unordered_map>

#include "hedra/core/error.h"
#include "hedra/core/face_geometry.h"
#include "hedra/core/parallel.h"
#include "hedra/core/predicates.h"
#include "hedra/core/tolerance.h"
#include "mesh/union_find.h"

namespace hedra {
namespace {

std::uint64_t key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

using internal::UnionFind;

// Whether a face with these loops passes Body's planarity check with room to spare: every
// vertex within half of kRoundingPlanarity times the loops' own scale (smaller than the body's)
// of the plane through the outer loop's vertex average with the Newell normal, as Body computes
// it; vertices exactly on the support triple's plane pass, as in Body. Cost O(loop sizes).
bool planar_after_rounding(const std::vector<Vec3>& v, const std::vector<std::vector<int>>& loops) {
  const Vec3 normal = newell_normal(v, loops);
  const double length = normal.norm();
  if (!(length > 0)) return false;
  const Vec3 unit = normal / length;
  Vec3 centre = Vec3::Zero();
  for (int w : loops[0]) centre += v[w];
  centre /= static_cast<double>(loops[0].size());
  Eigen::AlignedBox3d box;
  double largest = 0;
  for (const auto& loop : loops)
    for (int w : loop) {
      box.extend(v[w]);
      largest = std::max(largest, v[w].cwiseAbs().maxCoeff());
    }
  const double tolerance = 0.5 * kRoundingPlanarity * std::max(largest, box.diagonal().norm());
  const std::array<int, 3> s = support_triple(v, loops[0], normal);
  if (s[2] < 0 || collinear(v[s[0]], v[s[1]], v[s[2]])) return false;
  for (const auto& loop : loops)
    for (int w : loop) {
      if (w == s[0] || w == s[1] || w == s[2]) continue;
      if (orient3d(v[s[0]], v[s[1]], v[s[2]], v[w]) == Sign::Zero) continue;  // exactly planar
      if (std::abs(unit.dot(v[w] - centre)) > tolerance) return false;
    }
  return true;
}

}  // namespace

namespace {

// Coplanar regions of a soup (steps 3 and 3b of merge_once), and with snapping the vertices
// moved onto the regions' planes (moved is empty otherwise).
struct CoplanarRegions {
  std::vector<int> region;                 // per polygon
  std::vector<int> seeds;                  // per region, its first polygon
  // Per region r, its polygons in order: member_list[member_start[r] … member_start[r + 1]).
  std::vector<int> member_start, member_list;
  std::span<const int> members(int r) const {
    return {member_list.data() + member_start[static_cast<size_t>(r)],
            member_list.data() + member_start[static_cast<size_t>(r) + 1]};
  }
  bool snapped = false;
  std::vector<Vec3> moved;
};

// `twin(p, i)`: the polygon across edge i of polygon p (from its vertex i to vertex i + 1),
// the one with the reverse directed edge, or −1 (a boundary edge of an open surface). `normals` and `supports` per polygon, every polygon of non-zero area unless
// `plane_ids` decide coplanarity.
// Cost O(n log n) plus O(R²) normal comparisons for R regions when snapping.
template <class Twin>
CoplanarRegions grow_and_snap(const std::vector<Vec3>& v, const std::vector<std::vector<int>>& polys,
                              const std::vector<Vec3>& normals,
                              const std::vector<std::array<int, 3>>& supports, const Twin& twin,
                              const std::vector<int>* plane_ids, const MergeOptions& options) {
  const int n = static_cast<int>(polys.size());
  CoplanarRegions out;
  // Step 3: grow coplanar regions from seeds, comparing against the seed's plane (so a
  // tolerance cannot drift along a chain of nearly coplanar polygons).
  std::vector<int>& region = out.region;
  std::vector<int>& seeds = out.seeds;
  region.assign(static_cast<size_t>(n), -1);
  std::vector<int> queue;
  for (int s = 0; s < n; ++s) {
    if (region[s] >= 0) continue;
    const int r = static_cast<int>(seeds.size());
    seeds.push_back(s);
    const auto& sup = supports[s];
    const Vec3 unit = normals[s].normalized();
    auto coplanar = [&](int q) {
      if (plane_ids) return (*plane_ids)[q] == (*plane_ids)[s];
      if (normals[q].dot(normals[s]) <= 0) return false;
      for (int w : polys[q]) {
        if (orient3d(v[sup[0]], v[sup[1]], v[sup[2]], v[w]) == Sign::Zero) continue;
        if (options.coplanar_tolerance > 0 &&
            std::abs(unit.dot(v[w] - v[sup[0]])) <= options.coplanar_tolerance)
          continue;
        return false;
      }
      return true;
    };
    queue.assign(1, s);
    region[s] = r;
    for (size_t head = 0; head < queue.size(); ++head) {
      const int q = queue[head];
      for (size_t i = 0; i < polys[q].size(); ++i) {
        int t = twin(q, i);
        if (t >= 0 && region[t] < 0 && coplanar(t)) {
          region[t] = r;
          queue.push_back(t);
        }
      }
    }
  }
  const int regions = static_cast<int>(seeds.size());
  // Members by a counting sort on the region: ascending polygons within each region.
  out.member_start.assign(static_cast<size_t>(regions) + 1, 0);
  for (int p = 0; p < n; ++p) ++out.member_start[static_cast<size_t>(region[p]) + 1];
  for (int r = 0; r < regions; ++r) out.member_start[r + 1] += out.member_start[r];
  out.member_list.resize(static_cast<size_t>(n));
  {
    std::vector<int> fill(out.member_start.begin(), out.member_start.end() - 1);
    for (int p = 0; p < n; ++p) out.member_list[static_cast<size_t>(fill[region[p]]++)] = p;
  }
  auto members = [&](int r) { return out.members(r); };

  // Step 3b (snapping, a positive coplanar tolerance without a planarity tolerance): a region
  // grown within the tolerance is not planar. It gets the plane fitted to it (area-weighted
  // normal, mean offset), and every vertex of such a region moves to the least-squares nearest
  // point on the planes of all regions around it (minimum-norm correction; on three or fewer
  // independent planes it lies on all of them), but only when that moves it by at most the
  // tolerance: the certified bound. Vertices of exactly planar regions only stay put.
  const bool snap = !plane_ids && options.coplanar_tolerance > 0 && options.planarity_tolerance < 0;
  out.snapped = snap;
  std::vector<Vec3>& moved = out.moved;
  if (snap) {
    moved = v;
    std::vector<char> loose(regions, 0);
    std::vector<Vec3> plane_normal(regions, Vec3::Zero());
    std::vector<double> plane_offset(regions, 0);
    for (int r = 0; r < regions; ++r) {
      const auto& sup = supports[seeds[r]];
      std::vector<int> corners;
      for (int p : members(r)) {
        plane_normal[r] += normals[p];
        for (int w : polys[p]) {
          corners.push_back(w);
          if (orient3d(v[sup[0]], v[sup[1]], v[sup[2]], v[w]) != Sign::Zero) loose[r] = 1;
        }
      }
      std::sort(corners.begin(), corners.end());
      corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
      if (!loose[r]) plane_normal[r] = normals[seeds[r]];
      plane_normal[r].normalize();
      if (loose[r]) {
        for (int w : corners) plane_offset[r] += plane_normal[r].dot(v[w]);
        plane_offset[r] /= static_cast<double>(corners.size());
      } else {
        plane_offset[r] = plane_normal[r].dot(v[sup[0]]);
      }
    }
    // Regions far apart on one plane within the tolerance (the walls of a row of holes) share
    // the first one's plane, so that later steps see one plane, as in the aligned part.
    // O(R²) normal comparisons for R regions, corners checked only for parallel pairs.
    {
      std::vector<std::vector<int>> corners_of(regions);
      for (int r = 0; r < regions; ++r) {
        for (int p : members(r)) corners_of[r].insert(corners_of[r].end(), polys[p].begin(), polys[p].end());
        std::sort(corners_of[r].begin(), corners_of[r].end());
        corners_of[r].erase(std::unique(corners_of[r].begin(), corners_of[r].end()), corners_of[r].end());
      }
      std::vector<char> taken(regions, 0);
      for (int r = 0; r < regions; ++r) {
        if (taken[r]) continue;
        for (int q = r + 1; q < regions; ++q) {
          if (taken[q] || plane_normal[r].dot(plane_normal[q]) < 1 - 1e-6) continue;
          bool same = true;
          for (int w : corners_of[q])
            same = same && std::abs(plane_normal[r].dot(v[w]) - plane_offset[r]) <= options.coplanar_tolerance;
          if (!same) continue;
          taken[q] = 1;
          plane_normal[q] = plane_normal[r];
          plane_offset[q] = plane_offset[r];
          loose[q] = loose[r] = 1;
        }
      }
    }
    std::vector<std::vector<int>> around(v.size());
    for (int p = 0; p < n; ++p)
      for (int w : polys[p]) around[w].push_back(region[p]);
    for (size_t w = 0; w < v.size(); ++w) {
      auto& rs = around[w];
      std::sort(rs.begin(), rs.end());
      rs.erase(std::unique(rs.begin(), rs.end()), rs.end());
      if (std::none_of(rs.begin(), rs.end(), [&](int r) { return loose[r] != 0; })) continue;
      Eigen::MatrixXd normals_at(rs.size(), 3);
      Eigen::VectorXd residual(rs.size());
      for (size_t i = 0; i < rs.size(); ++i) {
        normals_at.row(static_cast<Eigen::Index>(i)) = plane_normal[rs[i]].transpose();
        residual[static_cast<Eigen::Index>(i)] = plane_offset[rs[i]] - plane_normal[rs[i]].dot(v[w]);
      }
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(normals_at, Eigen::ComputeThinU | Eigen::ComputeThinV);
      svd.setThreshold(1e-9);
      const Vec3 step = svd.solve(residual);
      if (step.allFinite() && step.norm() <= options.coplanar_tolerance) moved[w] = v[w] + step;
    }
  }
  return out;
}

std::vector<Body> merge_once(const PolygonSoup& input, const std::vector<int>* plane_ids,
                             const MergeOptions& options) {
  // Step 1: drop vertices no polygon uses, then the combinatorial checks on the soup. When
  // every vertex is used (a clean file), the input is read in place, not copied.
  PolygonSoup remapped;
  const PolygonSoup* source = &input;
  {
    std::vector<int> remap(input.vertices.size(), -1);
    for (const auto& poly : input.polygons)
      for (int v : poly)
        if (v >= 0 && static_cast<size_t>(v) < remap.size()) remap[v] = 0;
    if (std::find(remap.begin(), remap.end(), -1) != remap.end()) {
      for (size_t v = 0; v < remap.size(); ++v)
        if (remap[v] == 0) {
          remap[v] = static_cast<int>(remapped.vertices.size());
          remapped.vertices.push_back(input.vertices[v]);
        }
      remapped.polygons = input.polygons;
      for (auto& poly : remapped.polygons)
        for (int& v : poly)
          if (v >= 0 && static_cast<size_t>(v) < remap.size()) v = remap[v];
      source = &remapped;
    }
  }
  const auto& v = source->vertices;
  const auto& polys = source->polygons;
  const int n = static_cast<int>(polys.size());
  // Half-edges polygon by polygon (corner i of p: first[p] + i), and the polygon across each.
  std::vector<int> across = check_polygon_mesh(v, polys);
  std::vector<int> first(static_cast<size_t>(n) + 1, 0);
  for (int p = 0; p < n; ++p) first[p + 1] = first[p] + static_cast<int>(polys[p].size());
  {
    std::vector<int> polygon_of(across.size());
    for (int p = 0; p < n; ++p)
      std::fill(polygon_of.begin() + first[p], polygon_of.begin() + first[p + 1], p);
    for (int& t : across) t = polygon_of[static_cast<size_t>(t)];
  }
  // The polygon with the reverse of edge i of polygon p (the surface is closed).
  auto twin = [&](int p, size_t i) { return across[static_cast<size_t>(first[p]) + i]; };

  // Step 2: per-polygon normal and exact supporting triple.
  std::vector<Vec3> normals(n);
  std::vector<std::array<int, 3>> supports(n);
  // Newell normals grow as the square of the coordinates: for a body of size 1e-100 their
  // products and squares underflow to 0. One power of two for all (exact, same weights)
  // brings them to the size of the squared unit.
  double max_abs = 0;
  for (const Vec3& p : v) max_abs = std::max(max_abs, p.cwiseAbs().maxCoeff());
  int exponent = 0;
  if (max_abs > 0 && std::isfinite(max_abs)) std::frexp(max_abs, &exponent);
  const double normal_scale = std::ldexp(1.0, -2 * exponent);
  // Each polygon on its own (in parallel, each result in its own place); the first polygon
  // of zero area is reported afterwards, so the message does not depend on the threads.
  std::vector<char> zero_area(static_cast<size_t>(n), 0);
  parallel_blocks(static_cast<size_t>(n), 0, 4096, [&](size_t begin, size_t end) {
    for (size_t p = begin; p < end; ++p) {
      const Vec3 oriented = oriented_normal(v, polys[p]);
      normals[p] = oriented * normal_scale;
      for (int axis = 0; axis < 3; ++axis)  // the scaling must not drop an exact sign
        if (oriented[axis] != 0 && normals[p][axis] == 0)
          normals[p][axis] = std::copysign(std::numeric_limits<double>::min(), oriented[axis]);
      // Exactly zero, as in Body: Eigen's isZero() is fuzzy (1e-12) and rejected real, tiny
      // triangles, such as the corner faces of decomposition pieces written to files.
      supports[p] = (normals[p].array() == 0).all() ? std::array<int, 3>{-1, -1, -1}
                                                    : support_triple(v, polys[p], normals[p]);
      zero_area[p] = supports[p][2] < 0 ||
                     collinear(v[supports[p][0]], v[supports[p][1]], v[supports[p][2]]);
    }
  });
  // With caller-given planes (exact pieces rounded to double), a triangle that rounding made
  // flat is still a known part of its plane's region and vanishes in the merged face; only
  // the faces built in the end must have area (Body checks them).
  if (!plane_ids)
    if (const auto it = std::find(zero_area.begin(), zero_area.end(), 1); it != zero_area.end())
      throw InvalidInput("polygon " + std::to_string(it - zero_area.begin()) + " has zero area");

  const CoplanarRegions grown = grow_and_snap(v, polys, normals, supports, twin, plane_ids, options);
  const std::vector<int>& region = grown.region;
  const std::vector<int>& seeds = grown.seeds;
  const int regions = static_cast<int>(seeds.size());
  const bool snap = grown.snapped;
  const std::vector<Vec3>& moved = grown.moved;
  const std::vector<Vec3>& mv = snap ? moved : v;

  // Step 4: each region's boundary loops become one face (outer loop first, then holes).
  // A region whose boundary touches itself, or that has several outer loops, stays split.
  // The faces of region r: merged[face_start[r] … face_start[r + 1]).
  std::vector<Face> merged;
  merged.reserve(static_cast<size_t>(regions));
  std::vector<int> face_start(static_cast<size_t>(regions) + 1, 0);
  for (int r = 0; r < regions; ++r) {
    const std::span<const int> members = grown.members(r);
    if (members.size() == 1) {
      // One polygon: its boundary is the polygon itself (its vertices are distinct), whether
      // it becomes the face or stays split.
      merged.emplace_back(polys[members[0]]);
      face_start[r + 1] = static_cast<int>(merged.size());
      continue;
    }
    std::unordered_map<int, std::pair<int, int>> next;  // from -> (to, uses)
    std::vector<std::pair<int, int>> order;             // boundary edges in input order
    bool pinched = false;
    Vec3 normal = Vec3::Zero();
    for (int p : members) {
      normal += normals[p];
      const auto& poly = polys[p];
      for (size_t i = 0; i < poly.size(); ++i) {
        int a = poly[i], b = poly[(i + 1) % poly.size()];
        if (region[twin(p, i)] == r) continue;
        if (!next.emplace(a, std::make_pair(b, 0)).second) pinched = true;
        order.emplace_back(a, b);
      }
    }
    std::vector<std::vector<int>> loops;
    int outers = 0;
    if (!pinched) {
      for (const auto& [a0, b0] : order) {
        if (next[a0].second) continue;
        std::vector<int> loop;
        int a = a0;
        while (!next[a].second) {
          next[a].second = 1;
          loop.push_back(a);
          a = next[a].first;
        }
        if (a != a0) { pinched = true; break; }
        bool outer = oriented_normal(mv, loop).dot(normal) > 0;
        outers += outer;
        if (outer) loops.insert(loops.begin(), std::move(loop));
        else loops.push_back(std::move(loop));
      }
    }
    // Caller-given planes are exact planes of points that were rounded since: a region so thin
    // that rounding tilts it (a sliver of a cut through nearly coplanar faces, a few 1e-9 wide)
    // would fail the body's planarity check as one face. Its polygons, each exactly planar in
    // double when a triangle, are kept instead.
    if ((plane_ids || snap) && !pinched && outers == 1 && !planar_after_rounding(mv, loops))
      pinched = true;
    if (pinched || outers != 1) {
      for (int p : members) merged.emplace_back(polys[p]);
    } else {
      merged.emplace_back(std::move(loops));
    }
    face_start[r + 1] = static_cast<int>(merged.size());
  }

  // Step 5: drop vertices that only two faces of different planes share: they lie on the line
  // where the two planes meet, between their two neighbours, and only split an edge in two
  // (corefinement and some exporters leave them). Decided combinatorially, so rounding of the
  // coordinates cannot change the decision.
  {
    std::vector<int> first_region(v.size(), -1), second_region(v.size(), -1), faces_at(v.size(), 0);
    for (int r = 0; r < regions; ++r)
      for (int f = face_start[r]; f < face_start[r + 1]; ++f)
        for (const auto& loop : merged[f].loops)
          for (int w : loop) {
            ++faces_at[w];
            if (first_region[w] < 0) first_region[w] = r;
            else if (second_region[w] < 0) second_region[w] = r;
          }
    std::vector<char> removable(v.size(), 0);
    bool any = false;
    for (size_t w = 0; w < v.size(); ++w) {
      removable[w] = faces_at[w] == 2 && second_region[w] >= 0 && first_region[w] != second_region[w];
      any = any || removable[w];
    }
    // A loop must keep three vertices; if it would not, its vertices stay (in every face).
    for (bool changed = any; changed;) {
      changed = false;
      for (const Face& face : merged)
        for (const auto& loop : face.loops) {
          size_t kept = 0;
          for (int w : loop) kept += !removable[w];
          if (kept >= 3) continue;
          for (int w : loop)
            if (removable[w]) { removable[w] = 0; changed = true; }
        }
    }
    if (any)
      for (Face& face : merged)
        for (auto& loop : face.loops)
          std::erase_if(loop, [&](int w) { return removable[w] != 0; });
  }

  // Step 6: connected components (polygons sharing an edge), one Body each.
  UnionFind components(n);
  for (int p = 0; p < n; ++p)
    for (size_t i = 0; i < polys[p].size(); ++i) components.unite(p, twin(p, i));
  std::vector<int> component_of_root(n, -1);
  std::vector<std::vector<int>> component_regions;
  for (int r = 0; r < regions; ++r) {
    int root = components.find(seeds[r]);
    if (component_of_root[root] < 0) {
      component_of_root[root] = static_cast<int>(component_regions.size());
      component_regions.emplace_back();
    }
    component_regions[component_of_root[root]].push_back(r);
  }
  std::vector<Body> bodies;
  BodyOptions body_options;
  body_options.planarity_tolerance = options.planarity_tolerance;
  for (size_t c = 0; c < component_regions.size(); ++c) {
    // Vertices keep their input order, so a body read from a clean file keeps its numbers.
    std::vector<int> remap(v.size(), -1);
    size_t face_count = 0;
    for (int r : component_regions[c]) {
      face_count += static_cast<size_t>(face_start[r + 1] - face_start[r]);
      for (int f = face_start[r]; f < face_start[r + 1]; ++f)
        for (const auto& loop : merged[f].loops)
          for (int w : loop) remap[w] = 0;
    }
    std::vector<Vec3> vertices;
    vertices.reserve(component_regions.size() == 1 ? v.size() : 0);
    for (size_t w = 0; w < v.size(); ++w)
      if (remap[w] == 0) {
        remap[w] = static_cast<int>(vertices.size());
        vertices.push_back(mv[w]);
      }
    // Each face belongs to one component: moved, not copied.
    std::vector<Face> faces;
    faces.reserve(face_count);
    for (int r : component_regions[c])
      for (int f = face_start[r]; f < face_start[r + 1]; ++f) {
        Face& face = merged[f];
        for (auto& loop : face.loops)
          for (int& w : loop) w = remap[w];
        faces.push_back(std::move(face));
      }
    try {
      bodies.emplace_back(std::move(vertices), std::move(faces), body_options);
    } catch (const InvalidInput& e) {
      if (component_regions.size() == 1) throw;
      throw InvalidInput("component " + std::to_string(c) + ": " + e.what());
    }
  }
  return bodies;
}

// Snapping (see merge_once) always gives a valid body for a valid input: where the snapped
// faces fail validation (a vertex that could not move within the tolerance, a merged face
// that rounding leaves non-planar), the soup is merged exactly instead, as without tolerance.
std::vector<Body> merge_tolerant(const PolygonSoup& input, const std::vector<int>* plane_ids,
                                 const MergeOptions& options) {
  if (plane_ids || !(options.coplanar_tolerance > 0) || options.planarity_tolerance >= 0)
    return merge_once(input, plane_ids, options);
  try {
    return merge_once(input, plane_ids, options);
  } catch (const InvalidInput&) {
    MergeOptions exact = options;
    exact.coplanar_tolerance = 0;
    return merge_once(input, plane_ids, exact);
  }
}

// Needles: triangles whose three distinct corners are exactly collinear, the middle one strictly
// between the others (what a mesher's filler of a T-junction is, or what float32 rounding makes
// of a thin triangle). The surface is the same without them: each is dropped and its middle
// corner m put into the polygon across its long side (edge b → a there becomes b → m → a), whose
// edges then meet the needle's two short sides' neighbours. `out` is the soup so mended; false
// when there is no needle, or one cannot be mended so (a directed edge used twice, no polygon
// across its long side, or another needle there). Exact (collinear, coordinate comparisons);
// cost O(n) expected for n corners. Only a soup that fails is mended (merge()).
bool without_needles(const PolygonSoup& in, PolygonSoup& out) {
  const auto& v = in.vertices;
  const auto& polys = in.polygons;
  const int n = static_cast<int>(polys.size());
  std::unordered_map<std::uint64_t, int> owner;  // directed edge -> polygon
  for (int p = 0; p < n; ++p) {
    const auto& poly = polys[static_cast<size_t>(p)];
    for (int w : poly)
      if (w < 0 || static_cast<size_t>(w) >= v.size()) return false;
    for (size_t i = 0; i < poly.size(); ++i)
      if (!owner.emplace(key(poly[i], poly[(i + 1) % poly.size()]), p).second) return false;
  }
  // Per needle: (long side a → b in its turning order, middle corner m).
  struct Needle {
    int p, a, b, m;
  };
  std::vector<Needle> needles;
  std::vector<char> is_needle(static_cast<size_t>(n), 0);
  for (int p = 0; p < n; ++p) {
    const auto& t = polys[static_cast<size_t>(p)];
    if (t.size() != 3) continue;
    const Vec3 &x = v[static_cast<size_t>(t[0])], &y = v[static_cast<size_t>(t[1])], &z = v[static_cast<size_t>(t[2])];
    if (x == y || y == z || z == x || !collinear(x, y, z)) continue;
    // Along the axis of the largest spread, distinct points of one line have distinct values.
    int axis = 0;
    (x.cwiseMax(y).cwiseMax(z) - x.cwiseMin(y).cwiseMin(z)).maxCoeff(&axis);
    for (int k = 0; k < 3; ++k) {
      const double lo = v[static_cast<size_t>(t[static_cast<size_t>((k + 1) % 3)])][axis];
      const double hi = v[static_cast<size_t>(t[static_cast<size_t>((k + 2) % 3)])][axis];
      const double mid = v[static_cast<size_t>(t[static_cast<size_t>(k)])][axis];
      if ((lo < mid && mid < hi) || (hi < mid && mid < lo)) {
        needles.push_back({p, t[static_cast<size_t>((k + 1) % 3)], t[static_cast<size_t>((k + 2) % 3)], t[static_cast<size_t>(k)]});
        is_needle[static_cast<size_t>(p)] = 1;
      }
    }
  }
  if (needles.empty()) return false;
  out.vertices = v;
  out.polygons = polys;
  for (const Needle& s : needles) {
    const auto it = owner.find(key(s.b, s.a));
    if (it == owner.end() || is_needle[static_cast<size_t>(it->second)]) return false;
    auto& q = out.polygons[static_cast<size_t>(it->second)];
    size_t i = 0;
    while (i < q.size() && !(q[i] == s.b && q[(i + 1) % q.size()] == s.a)) ++i;
    if (i == q.size()) return false;
    q.insert(q.begin() + static_cast<std::ptrdiff_t>(i + 1), s.m);
  }
  std::vector<std::vector<int>> kept;
  kept.reserve(out.polygons.size() - needles.size());
  for (int p = 0; p < n; ++p)
    if (!is_needle[static_cast<size_t>(p)]) kept.push_back(std::move(out.polygons[static_cast<size_t>(p)]));
  out.polygons = std::move(kept);
  return true;
}

// A soup that fails only for its needles is merged without them; any other failure, or one that
// mending does not cure, is reported as the input's (its polygon numbers). What is not checked
// here is not checked for any soup: a surface lying on itself is found by the self-intersection
// test of its bodies (hedra/mesh/self_intersection.h), which readers run.
std::vector<Body> merge(const PolygonSoup& input, const std::vector<int>* plane_ids,
                        const MergeOptions& options) {
  if (plane_ids) return merge_once(input, plane_ids, options);
  try {
    return merge_tolerant(input, plane_ids, options);
  } catch (const InvalidInput&) {
    const std::exception_ptr first = std::current_exception();
    PolygonSoup mended;
    if (!without_needles(input, mended)) throw;
    try {
      return merge_tolerant(mended, plane_ids, options);
    } catch (const InvalidInput&) {
    }
    std::rethrow_exception(first);
  }
}

}  // namespace

SnappedSurface snap_surface(const PolygonSoup& soup, double tolerance) {
  const auto& v = soup.vertices;
  const auto& polys = soup.polygons;
  const int n = static_cast<int>(polys.size());
  // Normals and supports as in merge_once (one power of two against underflow).
  double max_abs = 0;
  for (const Vec3& p : v) max_abs = std::max(max_abs, p.cwiseAbs().maxCoeff());
  int exponent = 0;
  if (max_abs > 0 && std::isfinite(max_abs)) std::frexp(max_abs, &exponent);
  const double normal_scale = std::ldexp(1.0, -2 * exponent);
  std::vector<Vec3> normals(static_cast<size_t>(n));
  std::vector<std::array<int, 3>> supports(static_cast<size_t>(n));
  std::unordered_map<std::uint64_t, int> owner;  // directed edge -> polygon
  for (int p = 0; p < n; ++p) {
    for (int w : polys[p])
      if (w < 0 || static_cast<size_t>(w) >= v.size())
        throw InvalidInput("polygon " + std::to_string(p) + " refers to a vertex out of range");
    const Vec3 oriented = oriented_normal(v, polys[p]);  // as in merge_once
    normals[p] = oriented * normal_scale;
    for (int axis = 0; axis < 3; ++axis)
      if (oriented[axis] != 0 && normals[p][axis] == 0)
        normals[p][axis] = std::copysign(std::numeric_limits<double>::min(), oriented[axis]);
    supports[p] = (normals[p].array() == 0).all() ? std::array<int, 3>{-1, -1, -1}
                                                  : support_triple(v, polys[p], normals[p]);
    if (supports[p][2] < 0 || collinear(v[supports[p][0]], v[supports[p][1]], v[supports[p][2]]))
      throw InvalidInput("polygon " + std::to_string(p) + " has zero area");
    for (size_t i = 0; i < polys[p].size(); ++i)
      if (!owner.emplace(key(polys[p][i], polys[p][(i + 1) % polys[p].size()]), p).second)
        throw InvalidInput("polygon " + std::to_string(p) + " repeats a directed edge");
  }
  auto twin = [&](int p, size_t i) {
    const auto& poly = polys[p];
    const auto it = owner.find(key(poly[(i + 1) % poly.size()], poly[i]));
    return it == owner.end() ? -1 : it->second;
  };
  MergeOptions options;
  options.coplanar_tolerance = tolerance;
  CoplanarRegions grown = grow_and_snap(v, polys, normals, supports, twin, nullptr, options);
  SnappedSurface out;
  out.vertices = grown.snapped ? std::move(grown.moved) : v;
  out.region = std::move(grown.region);
  return out;
}

std::vector<Body> bodies_from_soup(const PolygonSoup& soup, const MergeOptions& options) {
  return merge(soup, nullptr, options);
}

std::vector<Body> bodies_from_soup(const PolygonSoup& soup, const std::vector<int>& plane_ids,
                                   const MergeOptions& options) {
  if (plane_ids.size() != soup.polygons.size())
    throw std::invalid_argument("bodies_from_soup: one plane id per polygon expected");
  return merge(soup, &plane_ids, options);
}

}  // namespace hedra
