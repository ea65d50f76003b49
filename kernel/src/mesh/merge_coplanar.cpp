#include "hedra/mesh/merge_coplanar.h"

#include <numeric>
#include <string>
#include <unordered_map>

#include "hedra/core/error.h"
#include "hedra/core/face_geometry.h"
#include "hedra/core/predicates.h"

namespace hedra {
namespace {

std::uint64_t key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // smallest id is the root
  }
};

}  // namespace

namespace {

std::vector<Body> merge(const PolygonSoup& input, const std::vector<int>* plane_ids,
                        const MergeOptions& options) {
  // Step 1: drop vertices no polygon uses, then the combinatorial checks on the soup.
  PolygonSoup soup;
  {
    std::vector<int> remap(input.vertices.size(), -1);
    for (const auto& poly : input.polygons)
      for (int v : poly)
        if (v >= 0 && static_cast<size_t>(v) < remap.size()) remap[v] = 0;
    for (size_t v = 0; v < remap.size(); ++v)
      if (remap[v] == 0) {
        remap[v] = static_cast<int>(soup.vertices.size());
        soup.vertices.push_back(input.vertices[v]);
      }
    soup.polygons = input.polygons;
    for (auto& poly : soup.polygons)
      for (int& v : poly)
        if (v >= 0 && static_cast<size_t>(v) < remap.size()) v = remap[v];
  }
  std::vector<Face> raw;
  raw.reserve(soup.polygons.size());
  for (const auto& poly : soup.polygons) raw.emplace_back(poly);
  check_polygon_mesh(soup.vertices, raw);

  const auto& v = soup.vertices;
  const auto& polys = soup.polygons;
  const int n = static_cast<int>(polys.size());

  // Step 2: per-polygon normal and exact supporting triple.
  std::vector<Vec3> normals(n);
  std::vector<std::array<int, 3>> supports(n);
  for (int p = 0; p < n; ++p) {
    normals[p] = newell_normal(v, polys[p]);
    supports[p] = normals[p].isZero() ? std::array<int, 3>{-1, -1, -1}
                                      : support_triple(v, polys[p], normals[p]);
    // With caller-given planes (exact pieces rounded to double), a triangle that rounding made
    // flat is still a known part of its plane's region and vanishes in the merged face; only
    // the faces built in the end must have area (Body checks them).
    if (!plane_ids &&
        (supports[p][2] < 0 || collinear(v[supports[p][0]], v[supports[p][1]], v[supports[p][2]])))
      throw InvalidInput("polygon " + std::to_string(p) + " has zero area");
  }
  std::unordered_map<std::uint64_t, int> owner;  // directed edge -> polygon
  for (int p = 0; p < n; ++p)
    for (size_t i = 0; i < polys[p].size(); ++i)
      owner[key(polys[p][i], polys[p][(i + 1) % polys[p].size()])] = p;
  auto twin = [&](int a, int b) { return owner.at(key(b, a)); };

  // Step 3: grow coplanar regions from seeds, comparing against the seed's plane (so a
  // tolerance cannot drift along a chain of nearly coplanar polygons).
  std::vector<int> region(n, -1);
  std::vector<int> seeds;
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
    std::vector<int> queue{s};
    region[s] = r;
    for (size_t head = 0; head < queue.size(); ++head) {
      const auto& poly = polys[queue[head]];
      for (size_t i = 0; i < poly.size(); ++i) {
        int t = twin(poly[i], poly[(i + 1) % poly.size()]);
        if (region[t] < 0 && coplanar(t)) {
          region[t] = r;
          queue.push_back(t);
        }
      }
    }
  }
  const int regions = static_cast<int>(seeds.size());
  std::vector<std::vector<int>> members(regions);
  for (int p = 0; p < n; ++p) members[region[p]].push_back(p);

  // Step 4: each region's boundary loops become one face (outer loop first, then holes).
  // A region whose boundary touches itself, or that has several outer loops, stays split.
  std::vector<std::vector<Face>> faces_of_region(regions);
  for (int r = 0; r < regions; ++r) {
    std::unordered_map<int, std::pair<int, int>> next;  // from -> (to, uses)
    std::vector<std::pair<int, int>> order;             // boundary edges in input order
    bool pinched = false;
    Vec3 normal = Vec3::Zero();
    for (int p : members[r]) {
      normal += normals[p];
      const auto& poly = polys[p];
      for (size_t i = 0; i < poly.size(); ++i) {
        int a = poly[i], b = poly[(i + 1) % poly.size()];
        if (region[twin(a, b)] == r) continue;
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
        bool outer = newell_normal(v, loop).dot(normal) > 0;
        outers += outer;
        if (outer) loops.insert(loops.begin(), std::move(loop));
        else loops.push_back(std::move(loop));
      }
    }
    if (pinched || outers != 1) {
      for (int p : members[r]) faces_of_region[r].emplace_back(polys[p]);
    } else {
      faces_of_region[r].emplace_back(std::move(loops));
    }
  }

  // Step 5: drop vertices that only two faces of different planes share: they lie on the line
  // where the two planes meet, between their two neighbours, and only split an edge in two
  // (corefinement and some exporters leave them). Decided combinatorially, so rounding of the
  // coordinates cannot change the decision.
  {
    std::vector<int> first_region(v.size(), -1), second_region(v.size(), -1), faces_at(v.size(), 0);
    for (int r = 0; r < regions; ++r)
      for (const Face& face : faces_of_region[r])
        for (const auto& loop : face.loops)
          for (int w : loop) {
            ++faces_at[w];
            if (first_region[w] < 0) first_region[w] = r;
            else if (second_region[w] < 0) second_region[w] = r;
          }
    std::vector<char> removable(v.size(), 0);
    for (size_t w = 0; w < v.size(); ++w)
      removable[w] = faces_at[w] == 2 && second_region[w] >= 0 && first_region[w] != second_region[w];
    // A loop must keep three vertices; if it would not, its vertices stay (in every face).
    for (bool changed = true; changed;) {
      changed = false;
      for (int r = 0; r < regions; ++r)
        for (const Face& face : faces_of_region[r])
          for (const auto& loop : face.loops) {
            size_t kept = 0;
            for (int w : loop) kept += !removable[w];
            if (kept >= 3) continue;
            for (int w : loop)
              if (removable[w]) { removable[w] = 0; changed = true; }
          }
    }
    for (int r = 0; r < regions; ++r)
      for (Face& face : faces_of_region[r])
        for (auto& loop : face.loops)
          std::erase_if(loop, [&](int w) { return removable[w] != 0; });
  }

  // Step 6: connected components (polygons sharing an edge), one Body each.
  UnionFind components(n);
  for (int p = 0; p < n; ++p)
    for (size_t i = 0; i < polys[p].size(); ++i)
      components.unite(p, twin(polys[p][i], polys[p][(i + 1) % polys[p].size()]));
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
    for (int r : component_regions[c])
      for (const Face& face : faces_of_region[r])
        for (const auto& loop : face.loops)
          for (int w : loop) remap[w] = 0;
    std::vector<Vec3> vertices;
    for (size_t w = 0; w < v.size(); ++w)
      if (remap[w] == 0) {
        remap[w] = static_cast<int>(vertices.size());
        vertices.push_back(v[w]);
      }
    std::vector<Face> faces;
    for (int r : component_regions[c])
      for (Face face : faces_of_region[r]) {
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

}  // namespace

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
