#include "hedra/scene/lod.h"

#include <gtest/gtest.h>

#include "hedra/io/scene_json.h"
#include "hedra/core/primitives.h"

namespace hedra {
namespace {

std::string sphere_scene(double distance) {
  return R"({"bodies": [{"name": "s", "sphere": {"center": [0, )" + std::to_string(distance) +
         R"(, 0], "radius": 2, "pixel_tolerance": 0.5}}],
            "camera": {"projection": "perspective", "eye": [0, 0, 0], "target": [0, 1, 0],
                       "up": [0, 0, 1], "fov_deg": 40},
            "image": {"width": 800, "height": 600}})";
}

TEST(Lod, FarSphereGetsFarFewerFacesBothWithinThePixelTolerance) {
  Scene near = io::parse_scene("near.json", sphere_scene(10));
  Scene far = io::parse_scene("far.json", sphere_scene(400));
  const Body& n = near.get("s").body;
  const Body& f = far.get("s").body;
  EXPECT_LT(f.face_count() * 10, n.face_count());
  // Independent check of the pixel bound: chordal error (r − distance from the centre to the
  // nearest face plane) over the pixel size at the sphere's nearest depth.
  for (auto [scene, centre_y] : {std::pair{&near, 10.0}, std::pair{&far, 400.0}}) {
    const Body& b = scene->get("s").body;
    double error = 0;
    for (int i = 0; i < b.face_count(); ++i)
      error = std::max(error, 2 - b.plane(i).value(Vec3(0, centre_y, 0)));
    const double pixel = scene->camera.pixel_size_at(Vec3(0, centre_y - 2, 0), 0);
    EXPECT_LE(error / pixel, 0.5) << centre_y;
    EXPECT_GT(error / pixel, 0.5 / 4) << centre_y;  // and not much finer than needed
  }
}

TEST(Lod, ParallelViewUsesTheFittedPictureSize) {
  Camera c = Camera::parallel({0, 0, -1}, {0, 1, 0});
  c.width = 1000;
  c.height = 1000;
  Eigen::AlignedBox3d box(Vec3(0, 0, 0), Vec3(90, 90, 10));
  const double h = parallel_view_height(c, box);
  EXPECT_NEAR(h, 100, 1e-12);  // 90 / (1 − 2·0.05)
  std::string note;
  EXPECT_NEAR(chordal_tolerance_for_pixels(2, Vec3(45, 45, 5), 5, c, h, &note), 0.2, 1e-12);
  EXPECT_NE(note.find("parallel"), std::string::npos);
}

}  // namespace
}  // namespace hedra
