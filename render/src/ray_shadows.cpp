#include "hedra/render/ray_shadows.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace hedra {
namespace {

constexpr int kBins = 16;
constexpr int kLeafSize = 4;
constexpr int kMaxSahDepth = 48;
constexpr int kStack = 128;

double half_area(const Eigen::AlignedBox3d& b) {
  if (b.isEmpty()) return 0;
  const Vec3 d = b.diagonal();
  return d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
}

struct Builder {
  const std::vector<Eigen::AlignedBox3d>& boxes;
  const std::vector<Vec3>& centres;
  std::vector<int>& order;
  std::vector<std::pair<Eigen::AlignedBox3d, std::array<int, 2>>>& out;  // box, (first|right, count)

  int build(int begin, int end, int depth) {
    Eigen::AlignedBox3d box, cbox;
    box.setEmpty();
    cbox.setEmpty();
    for (int i = begin; i < end; ++i) {
      box.extend(boxes[order[i]]);
      cbox.extend(centres[order[i]]);
    }
    const int node = static_cast<int>(out.size());
    out.push_back({box, {begin, end - begin}});
    const int n = end - begin;
    if (n <= kLeafSize) return node;
    // Binned surface-area heuristic over the widest axis of the centres.
    int axis = 0;
    const Vec3 extent = cbox.diagonal();
    if (extent.y() > extent[axis]) axis = 1;
    if (extent.z() > extent[axis]) axis = 2;
    int mid = begin + n / 2;
    // Deep chains (unlucky heuristic splits) fall back to median splits, which bounds the
    // depth by kMaxSahDepth + log2(n) and so the traversal stack.
    if (extent[axis] > 0 && depth < kMaxSahDepth) {
      std::array<Eigen::AlignedBox3d, kBins> bin_box;
      std::array<int, kBins> bin_count{};
      for (auto& b : bin_box) b.setEmpty();
      const double lo = cbox.min()[axis], scale = kBins / extent[axis];
      auto bin_of = [&](int t) {
        return std::min(kBins - 1, static_cast<int>((centres[t][axis] - lo) * scale));
      };
      for (int i = begin; i < end; ++i) {
        const int b = bin_of(order[i]);
        bin_box[b].extend(boxes[order[i]]);
        ++bin_count[b];
      }
      std::array<double, kBins> right_cost{};
      Eigen::AlignedBox3d acc;
      acc.setEmpty();
      int count = 0;
      for (int b = kBins - 1; b > 0; --b) {
        acc.extend(bin_box[b]);
        count += bin_count[b];
        right_cost[b] = half_area(acc) * count;
      }
      acc.setEmpty();
      count = 0;
      double best = INFINITY;
      int best_split = -1;
      for (int b = 0; b < kBins - 1; ++b) {
        acc.extend(bin_box[b]);
        count += bin_count[b];
        const double cost = half_area(acc) * count + right_cost[b + 1];
        if (count > 0 && count < n && cost < best) best = cost, best_split = b;
      }
      if (best_split >= 0) {
        const auto it = std::partition(order.begin() + begin, order.begin() + end,
                                       [&](int t) { return bin_of(t) <= best_split; });
        mid = static_cast<int>(it - order.begin());
      }
    }
    if (mid == begin + n / 2)
      std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                       [&](int a, int b) { return centres[a][axis] < centres[b][axis]; });
    build(begin, mid, depth + 1);
    const int right = build(mid, end, depth + 1);
    out[node].second = {right, 0};
    return node;
  }
};

}  // namespace

ShadowBvh::ShadowBvh(const SceneGeometry& geometry) {
  const size_t n = geometry.triangles.size();
  std::vector<Eigen::AlignedBox3d> boxes(n);
  std::vector<Vec3> centres(n);
  std::vector<int> order(n);
  for (size_t i = 0; i < n; ++i) {
    const auto& t = geometry.triangles[i];
    boxes[i].setEmpty();
    for (int k = 0; k < 3; ++k) boxes[i].extend(geometry.positions[t.v[k]]);
    centres[i] = boxes[i].center();
    order[i] = static_cast<int>(i);
  }
  if (n == 0) return;
  std::vector<std::pair<Eigen::AlignedBox3d, std::array<int, 2>>> out;
  Builder{boxes, centres, order, out}.build(0, static_cast<int>(n), 0);
  nodes_.reserve(out.size());
  for (const auto& [box, v] : out) nodes_.push_back({box, v[0], v[1]});
  triangles_.reserve(n);
  for (int i : order) {
    const auto& t = geometry.triangles[i];
    const Vec3& a = geometry.positions[t.v[0]];
    triangles_.push_back({a, geometry.positions[t.v[1]] - a, geometry.positions[t.v[2]] - a, t.face});
  }
}

bool ShadowBvh::occluded(const Vec3& origin, const Vec3& dir, double t_min, double t_max,
                         int skip_face) const {
  if (nodes_.empty()) return false;
  const Vec3 inv(1 / dir.x(), 1 / dir.y(), 1 / dir.z());
  int stack[kStack];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[static_cast<size_t>(stack[--top])];
    // Slab test (IEEE infinities handle axis-parallel rays).
    double t0 = t_min, t1 = t_max;
    for (int k = 0; k < 3; ++k) {
      double a = (node.box.min()[k] - origin[k]) * inv[k];
      double b = (node.box.max()[k] - origin[k]) * inv[k];
      if (a > b) std::swap(a, b);
      if (std::isnan(a) || std::isnan(b)) continue;  // 0·∞: origin on the slab, direction parallel
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
    }
    if (t0 > t1) continue;
    if (node.count == 0) {
      const int self = static_cast<int>(&node - nodes_.data());
      stack[top++] = node.first;
      stack[top++] = self + 1;
      continue;
    }
    for (int i = node.first; i < node.first + node.count; ++i) {
      const Triangle& tri = triangles_[static_cast<size_t>(i)];
      if (tri.face == skip_face) continue;
      // Möller–Trumbore, edges included.
      const Vec3 p = dir.cross(tri.e2);
      const double det = tri.e1.dot(p);
      if (det == 0) continue;
      const double inv_det = 1 / det;
      const Vec3 s = origin - tri.a;
      const double u = s.dot(p) * inv_det;
      if (u < 0 || u > 1) continue;
      const Vec3 q = s.cross(tri.e1);
      const double v = dir.dot(q) * inv_det;
      if (v < 0 || u + v > 1) continue;
      const double t = tri.e2.dot(q) * inv_det;
      if (t > t_min && t < t_max) return true;
    }
  }
  return false;
}

}  // namespace hedra
