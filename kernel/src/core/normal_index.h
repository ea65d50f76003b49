// Internal: unit normals indexed by cells, so that the planes whose normals lie near a
// direction are found without scanning them all. Shared by the decomposition's canonical
// planes (decompose/split.cpp, piece_of) and the plane solid's groups of faces
// (core/exact_solid.cpp, plane_solid). It only proposes candidates; the callers decide.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "hedra/core/plane.h"

namespace hedra::internal {

class NormalIndex {
 public:
  /// Adds the next id (0, 1, 2, … in the order added) with unit normal n. Cost O(1).
  void add(const Vec3& n) { cells_[key(cell(n.x()), cell(n.y()), cell(n.z()))].push_back(count_++); }
  int size() const { return count_; }

  /// The ids whose normal lies within `eps` (per component) of n, and of −n where
  /// `both_orientations`, ascending, each once; every id when eps is not small against the
  /// cells. Cost O(cells visited + ids found).
  std::vector<int> near(const Vec3& n, double eps, bool both_orientations) const {
    std::vector<int> out;
    if (!(eps < kCell / 4)) {
      out.resize(static_cast<size_t>(count_));
      std::iota(out.begin(), out.end(), 0);
      return out;
    }
    for (double sign : {1.0, -1.0}) {
      if (sign < 0 && !both_orientations) break;
      const Vec3 m = sign * n;
      for (long ix = cell(m.x() - eps); ix <= cell(m.x() + eps); ++ix)
        for (long iy = cell(m.y() - eps); iy <= cell(m.y() + eps); ++iy)
          for (long iz = cell(m.z() - eps); iz <= cell(m.z() + eps); ++iz) {
            auto it = cells_.find(key(ix, iy, iz));
            if (it != cells_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
          }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

 private:
  static constexpr double kCell = 1e-3;
  static long cell(double x) { return static_cast<long>(std::floor(x / kCell)); }
  static std::uint64_t key(long ix, long iy, long iz) {
    auto u = [](long i) { return static_cast<std::uint64_t>(i + 4096) & 0x1fffff; };
    return (u(ix) << 42) | (u(iy) << 21) | u(iz);
  }
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
  int count_ = 0;
};

}  // namespace hedra::internal
