#include "cli/demo.h"

#include "kernel/primitives.h"

namespace hedra::cli {

std::vector<NamedBody> demo_scene() {
  std::vector<NamedBody> scene;
  scene.push_back({"ground", box({-2, -2, -1}, {14, 10, 0})});
  scene.push_back({"L", prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2)});
  scene.push_back({"box", box({6, 0, 0}, {8, 2, 3}).rotated_z(30, {7, 1, 0})});
  scene.push_back({"pyramid", pyramid({{9, 4}, {12, 4}, {12, 7}, {9, 7}}, 0, {10.5, 5.5, 4})});
  return scene;
}

}  // namespace hedra::cli
