#include "hedra/scene/demo.h"

#include "hedra/core/primitives.h"

namespace hedra {

Scene demo_scene() {
  Scene scene;
  scene.add("ground", box({-2, -2, -1}, {14, 10, 0})).with_color({0.75, 0.75, 0.7});
  scene.add("L", prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2))
      .with_color({0.8, 0.55, 0.35});
  scene.add("box", box({6, 0, 0}, {8, 2, 3}).rotated_z(30, {7, 1, 0})).with_color({0.35, 0.5, 0.8});
  scene.add("pyramid", pyramid({{9, 4}, {12, 4}, {12, 7}, {9, 7}}, 0, {10.5, 5.5, 4}))
      .with_color({0.85, 0.75, 0.3});
  scene.camera = Camera::perspective({-6, -14, 12}, {6, 4, 0}, 40);
  scene.camera.width = 1024;
  scene.camera.height = 768;
  scene.lights.push_back(Light::sun(52.52, 13.40, UtcTime::parse("2026-06-21T10:00:00Z")));
  return scene;
}

}  // namespace hedra
