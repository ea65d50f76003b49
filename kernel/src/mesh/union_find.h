// Disjoint sets over 0 … n−1 (path halving), for grouping faces: Booleans and coplanar merging.
#pragma once

#include <algorithm>
#include <numeric>
#include <vector>

namespace hedra::internal {

/// Union–find whose root is always the smallest id of its set, so groupings do not depend on
/// the order of the unions. Cost: amortised near O(1) per operation.
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

}  // namespace hedra::internal
