// Build a body and print its body matrix (the README's example).
#include <iostream>

#include <hedra/hedra.h>

int main() {
  using namespace hedra;
  Body l = prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2);  // an L-shaped block
  Body tower = box({0, 0, 0}, {2, 2, 10}).rotated_z(30).translated({5, 0, 0});
  std::cout << "L body matrix (columns a, b, c, d per face):\n" << l.matrix() << "\n";
  std::cout << "L convex: " << convexity(l).convex << ", volume " << l.volume() << "\n";
  std::cout << "tower volume " << tower.volume() << ", convex " << convexity(tower).convex << "\n";
}
