// The raster renderer (hedra/render/raster.h): pixel tests on small images against formulas and
// independent oracles (ray casting for visibility, the exact shadow polygons and the exact point
// test of hedra/visibility/shadows.h for shadows), and golden images.
#include "hedra/render/raster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <set>

#include "hedra/io/png.h"
#include "hedra/io/scene_json.h"
#include "hedra/core/error.h"
#include "hedra/core/primitives.h"
#include "hedra/visibility/shadows.h"
#include "hedra/core/smooth_surface.h"
#include "hedra/render/shadow_map.h"
#include "testing/temp_files.h"

namespace hedra {
namespace {

namespace fs = std::filesystem;

// ---- Oracles and helpers ----

struct Hit {
  int body = -1, face = -1;
  double t = INFINITY;
  bool ambiguous = false;  // another face lies within a rounding distance of the nearest
};

// Nearest face along the ray of a sample, by brute-force ray casting against every triangle
// of every visible body.
Hit cast(const Scene& scene, const Vec3& origin, const Vec3& dir) {
  Hit best;
  double second = INFINITY;
  int second_body = -1, second_face = -1;
  for (size_t b = 0; b < scene.bodies().size(); ++b) {
    const SceneBody& sb = scene.bodies()[b];
    if (sb.hidden) continue;
    const Body& body = sb.body;
    for (const Triangle& tri : body.triangles()) {
      const Vec3 &a = body.vertices()[tri.v[0]], &p1 = body.vertices()[tri.v[1]],
                 &p2 = body.vertices()[tri.v[2]];
      const Vec3 e1 = p1 - a, e2 = p2 - a, p = dir.cross(e2);
      const double det = e1.dot(p);
      if (std::abs(det) < 1e-300) continue;
      const Vec3 s = origin - a;
      const double u = s.dot(p) / det;
      const Vec3 q = s.cross(e1);
      const double v = dir.dot(q) / det, t = e2.dot(q) / det;
      const double tol = 1e-9;
      if (u < -tol || v < -tol || u + v > 1 + tol || !(t > 0)) continue;
      if (t < best.t) {
        if (best.body != static_cast<int>(b) || best.face != tri.face) {
          second = best.t, second_body = best.body, second_face = best.face;
        }
        best.t = t, best.body = static_cast<int>(b), best.face = tri.face;
      } else if (t < second && (static_cast<int>(b) != best.body || tri.face != best.face)) {
        second = t, second_body = static_cast<int>(b), second_face = tri.face;
      }
    }
  }
  (void)second_body;
  (void)second_face;
  best.ambiguous = second - best.t < 1e-7 * std::max(1.0, best.t);
  return best;
}

// The world ray of sample (c, r) of a record.
void sample_ray(const SampleRecord& rec, int c, int r, Vec3* origin, Vec3* dir) {
  const double g = static_cast<double>(rec.columns) / rec.view.width();
  const double sx = (c + 0.5) / g, sy = (r + 0.5) / g;
  *dir = rec.view.ray_direction(sx, sy);
  *origin = rec.view.is_perspective() ? rec.view.eye() : rec.view.point_at(sx, sy, -1e4);
}

Vec3 sample_point(const SampleRecord& rec, int c, int r) {
  const double g = static_cast<double>(rec.columns) / rec.view.width();
  const size_t i = static_cast<size_t>(r) * rec.columns + c;
  return rec.view.point_at((c + 0.5) / g, (r + 0.5) / g, rec.key[i]);
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * d)).norm();
}

// Distance from p to the boundary of the shadow polygons of one face.
double edge_distance(const std::vector<ShadowPolygon>& polygons, const Vec3& p) {
  double best = INFINITY;
  auto ring = [&](const Polygon3& r) {
    for (size_t i = 0; i < r.size(); ++i) best = std::min(best, segment_distance(p, r[i], r[(i + 1) % r.size()]));
  };
  for (const ShadowPolygon& poly : polygons) {
    ring(poly.outer);
    for (const Polygon3& h : poly.holes) ring(h);
  }
  return best;
}

int channel(const Image& image, int x, int y, int k) { return image.pixel(x, y)[static_cast<size_t>(k)]; }

int expected_byte(double v) { return static_cast<int>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); }

// A ground slab with a rotated box and a pyramid on it, a directional light and a point
// light, seen in perspective: the shadow scenes of the tests.
Scene shadow_scene() {
  Scene scene;
  scene.add("ground", box({-10, -10, -1}, {10, 10, 0})).with_color({0.7, 0.7, 0.65});
  scene.add("block", box({-2, -1, 0}, {1, 1.5, 3}).rotated_z(20, {0, 0, 0})).with_color({0.8, 0.5, 0.3});
  scene.add("roof", pyramid({{3, -4}, {6, -4}, {6, -1}, {3, -1}}, 0, {4.5, -2.5, 4})).with_color({0.4, 0.5, 0.8});
  scene.camera = Camera::perspective({-13, -17, 15}, {0.3, -0.2, 0.1}, 42);
  scene.camera.width = 120;
  scene.camera.height = 90;
  scene.lights.push_back(Light::directional({-1, -2, -3}, 0.9));
  scene.lights.push_back(Light::point({4, 5, 9}, 0.6));
  return scene;
}

// ---- Options ----

TEST(RasterOptions, ParsesShadowMethods) {
  EXPECT_EQ(ShadowSettings::parse("none").method, ShadowSettings::Method::None);
  EXPECT_EQ(ShadowSettings::parse("exact").method, ShadowSettings::Method::Exact);
  const ShadowSettings m = ShadowSettings::parse("map:1024:2.5");
  EXPECT_EQ(m.method, ShadowSettings::Method::Map);
  EXPECT_EQ(m.map_resolution, 1024);
  EXPECT_EQ(m.map_bias, 2.5);
  EXPECT_EQ(ShadowSettings::parse("map:512").map_resolution, 512);
  EXPECT_EQ(ShadowSettings::parse("rays:16").ray_samples, 16);
  EXPECT_EQ(ShadowSettings::parse("rays").ray_samples, 1);
  for (const char* bad : {"", "map:", "map:8", "map:1024:-1", "map:1024:1:2", "rays:0", "rays:1.5",
                          "exact:3", "shadow", "map:abc"})
    EXPECT_THROW(ShadowSettings::parse(bad), InvalidInput) << bad;
  EXPECT_EQ(ShadowSettings::parse("map:1024:2.5").to_string(), "map:1024:2.5");
}

TEST(RasterOptions, ParsesAttenuation) {
  EXPECT_EQ(Attenuation::parse("none").model, Attenuation::Model::None);
  const Attenuation l = Attenuation::parse("linear:2.5");
  EXPECT_EQ(l.model, Attenuation::Model::Linear);
  EXPECT_EQ(l.k, 2.5);
  const Attenuation q = Attenuation::parse("quadratic:1,0.1,0.01");
  EXPECT_EQ(q.model, Attenuation::Model::Quadratic);
  EXPECT_EQ(q.c, 0.01);
  for (const char* bad : {"linear", "linear:0", "quadratic:1,2", "quadratic:0,0,0", "cubic:1"})
    EXPECT_THROW(Attenuation::parse(bad), InvalidInput) << bad;
}

TEST(RasterOptions, RejectsBadSettings) {
  Scene scene;
  scene.add("b", box({0, 0, 0}, {1, 1, 1}));
  RenderOptions o;
  o.width = o.height = 8;
  o.aa = 3;
  EXPECT_THROW(render(scene, o), InvalidInput);
  o.aa = 1;
  o.width = 0;
  o.height = 70000;
  EXPECT_THROW(render(scene, o), InvalidInput);
}

// ---- Lighting ----

// One face seen face-on by the course's viewer (docs/algorithms.md §6.1) at +∞ on z under a
// directional light: every pixel of it has I = I_a k_a C + I_l [k_d (n̂·L̂) C + k_s (R̂·Ŝ)^n]
// exactly (rounded to 8 bits), in each shading mode.
TEST(RasterLighting, SingleLitFaceHasTheFormulaIntensity) {
  Scene scene;
  Material m;
  m.color = Vec3(0.8, 0.6, 0.4);
  m.ka = 0.2, m.kd = 0.7, m.ks = 0.3, m.shininess = 10;
  scene.add("slab", box({-3, -3, -1}, {3, 3, 0}), m);
  scene.lights.push_back(Light::directional({-1, 0, -1}, 0.9));
  const double cos_theta = std::sqrt(0.5);  // n = (0,0,1), L̂ = (1,0,1)/√2
  const double r_dot_s = std::sqrt(0.5);    // R̂ = (−1,0,1)/√2, Ŝ = (0,0,1)
  for (Shading shading : {Shading::Flat, Shading::Gouraud, Shading::Phong}) {
    RenderOptions o;
    o.shadows.method = ShadowSettings::Method::None;  // lighting only
    o.width = o.height = 24;
    o.shading = shading;
    const Image image = render(scene, o);
    for (int k = 0; k < 3; ++k) {
      const double c = m.color[k];
      const double expected = 0.2 * c + 0.9 * (0.7 * cos_theta * c + 0.3 * std::pow(r_dot_s, 10));
      for (int y = 4; y < 20; ++y)
        for (int x = 4; x < 20; ++x)
          ASSERT_EQ(channel(image, x, y, k), expected_byte(expected))
              << "shading " << static_cast<int>(shading) << " pixel " << x << "," << y;
    }
  }
}

// Phong shading under point and spot lights with both attenuation models: each pixel equals
// the formula evaluated at its own world point.
TEST(RasterLighting, PointAndSpotLightsWithAttenuationFollowTheFormula) {
  Scene scene;
  Material m;
  m.color = Vec3(0.9, 0.7, 0.5);
  m.ka = 0.1, m.kd = 0.8, m.ks = 0.4, m.shininess = 8;
  scene.add("slab", box({-5, -5, -1}, {5, 5, 0}), m);
  scene.camera = Camera::perspective({1, -2, 12}, {0, 0, 0}, 50);
  Light point = Light::point({1.5, 1, 3}, 0.8);
  point.color = Vec3(1, 0.9, 0.8);
  scene.lights.push_back(point);
  scene.lights.push_back(Light::spot({-1, -1, 4}, {0.2, 0.1, -1}, 30, 2, 0.7));
  for (const std::string att : {"none", "linear:3", "quadratic:1,0.2,0.05"}) {
    RenderOptions o;
    o.shadows.method = ShadowSettings::Method::None;  // lighting only
    o.width = o.height = 32;
    o.ambient = 0.5;
    o.attenuation = Attenuation::parse(att);
    SampleRecord rec;
    const Image image = render(scene, o, &rec);
    int checked = 0;
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        if (rec.body[static_cast<size_t>(y) * 32 + x] != 0 || rec.face[static_cast<size_t>(y) * 32 + x] != 5) continue;
        const Vec3 p = sample_point(rec, x, y);
        const Vec3 n(0, 0, 1), v = (scene.camera.eye - p).normalized();
        Vec3 expected = 0.5 * m.ka * m.color;
        const double viewer = o.attenuation.model == Attenuation::Model::Linear
                                  ? 1 / ((p - scene.camera.eye).norm() + 3)
                                  : 1.0;
        for (const Light& l : scene.lights) {
          Vec3 to = l.position - p;
          const double d = to.norm();
          to /= d;
          double f = viewer;
          if (l.type == Light::Type::Spot) {
            const double c = -to.dot(l.direction.normalized());
            if (c < std::cos(l.cone_deg * std::numbers::pi / 180)) continue;
            f *= std::pow(c, l.falloff);
          }
          if (o.attenuation.model == Attenuation::Model::Quadratic) f /= 1 + 0.2 * d + 0.05 * d * d;
          const double ndl = n.dot(to);
          if (ndl <= 0) continue;
          const Vec3 r = 2 * ndl * n - to;
          const double spec = r.dot(v) > 0 ? m.ks * std::pow(r.dot(v), m.shininess) : 0;
          expected += f * l.intensity * l.color.cwiseProduct(m.kd * ndl * m.color + Vec3::Constant(spec));
        }
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(channel(image, x, y, k), expected_byte(expected[k]), 1) << att;
        ++checked;
      }
    EXPECT_GT(checked, 500) << att;
  }
}

// A highlight in the middle of one large face: Phong (normals, light and view vectors per
// pixel) shows it; Gouraud interpolates the corners' intensities and cannot.
TEST(RasterLighting, PhongShowsAHighlightInsideAFaceGouraudDoesNot) {
  Scene scene;
  Material m;
  m.color = Vec3(0.3, 0.3, 0.6);
  m.ka = 0.1, m.kd = 0.3, m.ks = 0.9, m.shininess = 60;
  scene.add("slab", box({-4, -4, -1}, {4, 4, 0}), m);
  scene.camera = Camera::perspective({0, -0.01, 6}, {0, 0, 0}, 70);
  scene.lights.push_back(Light::point({0, 0, 6}, 1.0));
  RenderOptions o;
  o.shadows.method = ShadowSettings::Method::None;  // lighting only
  o.width = o.height = 41;
  o.shading = Shading::Phong;
  const Image phong = render(scene, o);
  o.shading = Shading::Gouraud;
  SampleRecord rec;
  const Image gouraud = render(scene, o, &rec);
  const int centre_phong = channel(phong, 20, 20, 0), centre_gouraud = channel(gouraud, 20, 20, 0);
  EXPECT_GT(centre_phong, 200);
  EXPECT_LT(centre_gouraud, 60);
  // Gouraud: no pixel of the face is brighter than its corners allow.
  int max_gouraud = 0, pixels = 0;
  for (int y = 0; y < 41; ++y)
    for (int x = 0; x < 41; ++x)
      if (rec.face[static_cast<size_t>(y) * 41 + x] == 5) {
        max_gouraud = std::max(max_gouraud, channel(gouraud, x, y, 0));
        ++pixels;
      }
  EXPECT_GT(pixels, 1000);
  EXPECT_LT(max_gouraud, 60);
}

// A tessellated sphere shades like the true sphere with Phong (analytic normals), while flat
// shading shows its facets; box edges stay sharp (no averaging across real edges).
TEST(RasterLighting, SmoothNormalsMakeASphereRoundAndKeepRealEdgesSharp) {
  Scene scene;
  Material m;
  m.color = Vec3(1, 1, 1);
  m.ka = 0, m.kd = 1, m.ks = 0;
  const Vec3 centre(0, 0, 0);
  scene.add("ball", sphere(centre, 2, 0.05), m).with_surface(SmoothSurface::sphere(centre, 2));
  scene.lights.push_back(Light::directional({-0.3, 0.4, -1}, 1.0));
  const Vec3 to_light = Vec3(0.3, -0.4, 1).normalized();
  RenderOptions o;
  o.shadows.method = ShadowSettings::Method::None;  // lighting only
  o.width = o.height = 64;
  double error[3] = {0, 0, 0};
  int counted = 0;
  for (Shading shading : {Shading::Flat, Shading::Gouraud, Shading::Phong}) {
    o.shading = shading;
    SampleRecord rec;
    const Image image = render(scene, o, &rec);
    counted = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        if (rec.body[static_cast<size_t>(y) * 64 + x] < 0) continue;
        const Vec3 p = sample_point(rec, x, y);
        const double expected = std::max(0.0, (p - centre).normalized().dot(to_light));
        error[static_cast<int>(shading)] += std::abs(channel(image, x, y, 0) - 255 * expected);
        ++counted;
      }
  }
  ASSERT_GT(counted, 1500);
  for (double& e : error) e /= counted;
  EXPECT_LT(error[2], 1.0);  // Phong: within a grey level on average
  EXPECT_GT(error[0], 3 * error[2]);  // flat: facets
  // Sharp edges: a box has one colour per visible face in every mode.
  Scene boxes;
  boxes.add("b", box({-1, -1, -1}, {1, 1, 1}).rotated_z(25).rotated_x(-30), m);
  boxes.lights.push_back(Light::directional({-0.3, 0.4, -1}, 1.0));
  o.shading = Shading::Phong;
  SampleRecord rec;
  const Image image = render(boxes, o, &rec);
  std::map<int, std::set<int>> values;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      if (rec.face[static_cast<size_t>(y) * 64 + x] >= 0)
        values[rec.face[static_cast<size_t>(y) * 64 + x]].insert(channel(image, x, y, 0));
  EXPECT_GE(values.size(), 2u);
  for (const auto& [face, set] : values) EXPECT_EQ(set.size(), 1u) << "face " << face;
}

TEST(SmoothSurface, FollowsItsBodyThroughAffineTransforms) {
  // An ellipsoid (a non-uniformly scaled, rotated, moved sphere): normals are gradients.
  const Transform t = Transform::scaling(Vec3(2, 1, 0.5)) * Transform::rotation_z(30) *
                      Transform::translation(Vec3(1, 2, 3));
  const SmoothSurface s = SmoothSurface::sphere(Vec3::Zero(), 1).transformed(t);
  const Vec3 local = Vec3(1, 2, 2).normalized();
  const Vec3 world = t.apply(local);
  // Gradient of |M⁻¹(p)|² in world coordinates, by central differences.
  const Transform inv = t.inverse();
  auto f = [&](const Vec3& p) { return inv.apply(p).squaredNorm(); };
  Vec3 grad;
  for (int k = 0; k < 3; ++k) {
    Vec3 e = Vec3::Zero();
    e[k] = 1e-6;
    grad[k] = (f(world + e) - f(world - e)) / 2e-6;
  }
  EXPECT_LT((s.normal(world, world) - grad.normalized()).norm(), 1e-6);
  // Cylinder: caps flat, sides curved, also after a rotation; cone: base flat.
  const SmoothSurface c = SmoothSurface::cylinder(1, 0, 2).transformed(Transform::rotation_x(90));
  EXPECT_FALSE(c.curved_face(Transform::rotation_x(90).apply_vector(Vec3(0, 0, 1))));
  EXPECT_TRUE(c.curved_face(Transform::rotation_x(90).apply_vector(Vec3(1, 0, 0))));
  const SmoothSurface cone = SmoothSurface::cone(1, 0, 3);
  EXPECT_FALSE(cone.curved_face(Vec3(0, 0, -1)));
  EXPECT_TRUE(cone.curved_face(Vec3(3, 0, 1).normalized()));
  // Cone normal: constant along a generator, tilted up by the slope.
  EXPECT_LT((cone.normal(Vec3(1, 0, 0), Vec3(0.5, 0, 1)) - Vec3(1, 0, 1.0 / 3).normalized()).norm(), 1e-12);
  EXPECT_LT((cone.normal(Vec3(0, 0, 3), Vec3(0.5, 0, 1)) - Vec3(1, 0, 1.0 / 3).normalized()).norm(), 1e-12);
  // A perspective transform gives no surface.
  EXPECT_FALSE(SmoothSurface::sphere(Vec3::Zero(), 1).transformed(Transform::perspective(10)).is_smooth());
}

TEST(SmoothSurface, SceneFilesRecordCurvedPrimitives) {
  const Scene scene = io::read_scene(std::string(HEDRA_SOURCE_DIR) + "/examples/city-block.json");
  EXPECT_EQ(scene.get("tower").surface.kind(), SmoothSurface::Kind::Cylinder);
  EXPECT_EQ(scene.get("s").surface.kind(), SmoothSurface::Kind::Sphere);
  EXPECT_EQ(scene.get("spire").surface.kind(), SmoothSurface::Kind::Cone);
  EXPECT_EQ(scene.get("L").surface.kind(), SmoothSurface::Kind::None);
}

// ---- Visibility ----

void expect_visibility_matches_ray_casting(const Scene& scene, int width, int height, int aa,
                                           int* compared_out = nullptr) {
  RenderOptions o;
  o.shadows.method = ShadowSettings::Method::None;  // lighting only
  o.width = width;
  o.height = height;
  o.aa = aa;
  SampleRecord rec;
  render(scene, o, &rec);
  int compared = 0, skipped = 0;
  for (int r = 0; r < rec.rows; ++r)
    for (int c = 0; c < rec.columns; ++c) {
      Vec3 origin, dir;
      sample_ray(rec, c, r, &origin, &dir);
      const Hit hit = cast(scene, origin, dir);
      if (hit.ambiguous) {
        ++skipped;
        continue;
      }
      const size_t i = static_cast<size_t>(r) * rec.columns + c;
      ASSERT_EQ(rec.body[i], hit.body) << "sample " << c << "," << r;
      ASSERT_EQ(rec.face[i], hit.face) << "sample " << c << "," << r;
      ++compared;
    }
  EXPECT_LT(skipped, compared / 50);
  if (compared_out) *compared_out = compared;
}

// Every sample shows the face a ray cast finds first: no hidden face of a box ever shows.
TEST(RasterVisibility, HiddenFacesNeverShow) {
  Scene scene;
  scene.add("box", box({-1, -1.5, -2}, {1.2, 1, 1.7}).rotated_z(33).rotated_x(21));
  scene.add("behind", box({-3, 2, -4}, {3, 3, -1}).rotated_y(12));
  scene.camera = Camera::parallel({-1, -2, -3}, {0, 0, 1});
  expect_visibility_matches_ray_casting(scene, 48, 40, 1);
  scene.camera = Camera::perspective({4, -7, 5}, {0, 0, 0}, 45);
  expect_visibility_matches_ray_casting(scene, 48, 40, 4);
}

// Two boxes that interpenetrate: the z-buffer switches between them exactly at their
// intersection line.
TEST(RasterVisibility, InterpenetratingBodiesMeetAtTheirIntersectionLine) {
  Scene scene;
  scene.add("a", box({-2, -1, -1}, {1, 1, 1}).rotated_z(17));
  scene.add("b", box({-0.5, -2, -0.6}, {2.5, 0.4, 0.8}).rotated_x(-23).rotated_y(9));
  scene.camera = Camera::perspective({3, -6, 4}, {0, 0, 0}, 40);
  int compared = 0;
  expect_visibility_matches_ray_casting(scene, 64, 48, 1, &compared);
  EXPECT_GT(compared, 1000);
}

// A body that reaches behind the eye is cut at the near plane: the image shows exactly what
// lies in front of the eye.
TEST(RasterVisibility, BodyStraddlingTheEyePlaneIsClipped) {
  Scene scene;
  scene.add("ground", box({-20, -20, -1}, {20, 20, 0}));
  scene.add("wall", box({-1, -15, 0}, {0, 15, 4}).rotated_z(10));
  scene.add("tower", box({3, 4, 0}, {5, 6, 7}));
  scene.camera = Camera::perspective({1, 0, 2}, {6, 6, 1}, 60);
  expect_visibility_matches_ray_casting(scene, 48, 36, 1);
}

TEST(RasterVisibility, OutputDoesNotDependOnThreadsOrTiles) {
  Scene scene = shadow_scene();
  RenderOptions o;
  o.shadows = ShadowSettings::parse("rays:4");
  o.aa = 4;
  o.threads = 1;
  o.tile_size = 8;
  const Image a = render(scene, o);
  o.threads = 2;
  o.tile_size = 32;
  const Image b = render(scene, o);
  EXPECT_EQ(a.rgb, b.rgb);
}

// ---- Shadows ----

// Exact shadows: a sample is dark for a light exactly when its point lies in a shadow polygon
// of that light on its face (or the face turns away from the light), checked against the
// polygons and, independently, against the exact point test of hedra/visibility/shadows.h.
TEST(RasterShadows, ExactShadowPixelsMatchTheShadowPolygons) {
  const Scene scene = shadow_scene();
  const ShadowResult exact = compute_shadows(scene);
  RenderOptions o;
  o.shadows.method = ShadowSettings::Method::Exact;
  SampleRecord rec;
  render(scene, o, &rec);
  int shadowed = 0, lit = 0, near_edge = 0;
  const int lights = static_cast<int>(scene.lights.size());
  for (int r = 0; r < rec.rows; ++r)
    for (int c = 0; c < rec.columns; ++c) {
      const size_t i = static_cast<size_t>(r) * rec.columns + c;
      if (rec.body[i] < 0) continue;
      const Vec3 p = sample_point(rec, c, r);
      for (int j = 0; j < lights; ++j) {
        const FaceShadow& fs = exact.face(j, rec.body[i], rec.face[i]);
        bool expected = fs.to_light != Facing::Front || point_in_polygons(fs.polygons, p);
        if (fs.to_light == Facing::Front && edge_distance(fs.polygons, p) < 1e-9) {
          ++near_edge;
          continue;
        }
        ASSERT_EQ(rec.shadow[i * lights + j], expected ? 1.0f : 0.0f)
            << "sample " << c << "," << r << " light " << j;
        // The independent oracle, on every 7th sample (it is slow).
        if ((r * rec.columns + c) % 7 == 0) {
          ASSERT_EQ(in_shadow(scene, scene.lights[j], rec.body[i], rec.face[i], p), expected);
        }
        (expected ? shadowed : lit)++;
      }
    }
  EXPECT_GT(shadowed, 1000);
  EXPECT_GT(lit, 1000);
  EXPECT_EQ(near_edge, 0);
}

// The rasterization of given polygons is exact at sample centres even for a polygon with a
// hole (even–odd interior) and at aa = 16.
TEST(RasterShadows, ExactMaskFollowsGivenPolygonsWithHoles) {
  Scene scene;
  scene.add("slab", box({-5, -4, -1}, {5, 4, 0}));
  scene.camera = Camera::perspective({-2, -9, 8}, {0, 0, 0}, 50);
  scene.lights.push_back(Light::directional({0.1, 0.2, -1}));
  SurfaceShadows polygons(1);
  SurfaceShadow s;
  s.body = 0;
  s.face = 5;  // z = max
  s.loops = {{{-3, -2.3, 0}, {3.7, -2.9, 0}, {2.2, 3.1, 0}, {-3.4, 2.6, 0}},
             {{-1.1, -0.7, 0}, {-0.6, 1.3, 0}, {1.4, 0.2, 0}}};
  polygons[0].push_back(s);
  RenderOptions o;
  o.width = 40;
  o.height = 30;
  o.aa = 16;
  o.shadows.method = ShadowSettings::Method::Exact;
  o.exact_polygons = &polygons;
  SampleRecord rec;
  render(scene, o, &rec);
  std::vector<ShadowPolygon> as_polygons(1);
  as_polygons[0].outer = s.loops[0];
  as_polygons[0].holes = {s.loops[1]};
  int in = 0, out = 0;
  for (int r = 0; r < rec.rows; ++r)
    for (int c = 0; c < rec.columns; ++c) {
      const size_t i = static_cast<size_t>(r) * rec.columns + c;
      if (rec.face[i] != 5) continue;
      const Vec3 p = sample_point(rec, c, r);
      if (edge_distance(as_polygons, p) < 1e-9) continue;
      const bool expected = point_in_polygons(as_polygons, p);
      ASSERT_EQ(rec.shadow[i], expected ? 1.0f : 0.0f) << c << "," << r;
      (expected ? in : out)++;
    }
  EXPECT_GT(in, 2000);
  EXPECT_GT(out, 2000);
}

// Shadow maps and shadow rays agree with the exact method away from shadow edges: rays
// everywhere but within rounding of an edge, maps beyond a margin of a few texels (plus what
// the bias moves) and on faces not too steep to the light (at grazing incidence a constant
// bias cannot prevent acne: the map's own failure mode, shown in ShadowMapWithoutBiasShowsAcne).
TEST(RasterShadows, MapAndRaysAgreeWithExactAwayFromShadowEdges) {
  Scene scene = shadow_scene();
  scene.lights.push_back(Light::spot({-6, 5, 8}, {0.6, -0.5, -1}, 40, 1, 0.5));
  const ShadowResult exact = compute_shadows(scene);
  const int lights = static_cast<int>(scene.lights.size());
  RenderOptions o;
  o.shadows.method = ShadowSettings::Method::Exact;
  SampleRecord reference;
  render(scene, o, &reference);
  struct Case {
    std::string method;
    double margin;  // world units (the scene is 20 wide)
  };
#ifdef HEDRA_SANITIZED
  const std::vector<Case> cases = {{"rays:1", 1e-9}, {"map:2048:3", 0.15}};  // a 4096² map is slow under ASan
#else
  const std::vector<Case> cases = {{"rays:1", 1e-9}, {"map:2048:3", 0.15}, {"map:4096:3", 0.08}};
#endif
  for (const Case& k : cases) {
    o.shadows = ShadowSettings::parse(k.method);
    SampleRecord rec;
    render(scene, o, &rec);
    int compared = 0;
    for (size_t i = 0; i < rec.body.size(); ++i) {
      ASSERT_EQ(rec.body[i], reference.body[i]);
      if (rec.body[i] < 0) continue;
      const int c = static_cast<int>(i % rec.columns), r = static_cast<int>(i / rec.columns);
      const Vec3 p = sample_point(rec, c, r);
      for (int j = 0; j < lights; ++j) {
        const FaceShadow& fs = exact.face(j, rec.body[i], rec.face[i]);
        if (fs.to_light == Facing::Front && edge_distance(fs.polygons, p) < k.margin) continue;
        if (k.method != "rays:1" && fs.to_light == Facing::Front) {
          const Light& l = scene.lights[j];
          const Vec3 to = l.at_infinity() ? Vec3(-l.direction.normalized()) : Vec3((l.position - p).normalized());
          const Vec3 n = -scene.bodies()[rec.body[i]].body.inner_normal(rec.face[i]);
          if (n.dot(to) < 0.3) continue;
        }
        ASSERT_EQ(rec.shadow[i * lights + j], reference.shadow[i * lights + j])
            << k.method << " sample " << c << "," << r << " light " << j << " body " << rec.body[i]
            << " face " << rec.face[i];
        ++compared;
      }
    }
    EXPECT_GT(compared, 12000) << k.method;
  }
}

// The failure modes of the shadow map are real: without bias, lit faces steep to the light
// shadow themselves (acne).
TEST(RasterShadows, ShadowMapWithoutBiasShowsAcne) {
  const Scene scene = shadow_scene();
  const ShadowResult exact = compute_shadows(scene);
  RenderOptions o;
  o.shadows = ShadowSettings::parse("map:512:0");
  SampleRecord rec;
  render(scene, o, &rec);
  int wrong = 0, lit = 0;
  for (size_t i = 0; i < rec.body.size(); ++i) {
    if (rec.body[i] < 0) continue;
    const FaceShadow& fs = exact.face(0, rec.body[i], rec.face[i]);
    const Vec3 p = sample_point(rec, static_cast<int>(i % rec.columns), static_cast<int>(i / rec.columns));
    if (fs.to_light != Facing::Front || point_in_polygons(fs.polygons, p)) continue;
    ++lit;
    wrong += rec.shadow[i * rec.lights] == 1.0f;
  }
  EXPECT_GT(wrong, lit / 20) << "expected acne on lit faces";
}

// Light 0 (directional) on the faces that face it: samples the exact polygons put in shadow
// but the method leaves lit (`leaks`), and the other way round (`extra`).
struct ShadowDisagreement {
  int leaks = 0, extra = 0, compared = 0, in_shadow = 0;
};
ShadowDisagreement disagreement(const Scene& scene, const ShadowResult& exact, const std::string& method,
                                int only_body = -1) {
  RenderOptions o;
  o.shadows = ShadowSettings::parse(method);
  SampleRecord rec;
  render(scene, o, &rec);
  ShadowDisagreement d;
  for (size_t i = 0; i < rec.body.size(); ++i) {
    if (rec.body[i] < 0 || (only_body >= 0 && rec.body[i] != only_body)) continue;
    const FaceShadow& fs = exact.face(0, rec.body[i], rec.face[i]);
    if (fs.to_light != Facing::Front) continue;
    const Vec3 p = sample_point(rec, static_cast<int>(i % rec.columns), static_cast<int>(i / rec.columns));
    const bool in = point_in_polygons(fs.polygons, p), got = rec.shadow[i * rec.lights] == 1.0f;
    d.in_shadow += in;
    d.leaks += in && !got;
    d.extra += !in && got;
    ++d.compared;
  }
  return d;
}

// A rotated block on the ground under a low directional light, seen from straight above: a
// long shadow whose edges run at angles to the shadow map's texels.
Scene low_sun_scene() {
  Scene scene;
  scene.add("ground", box({-10, -10, -1}, {10, 10, 0}));
  scene.add("block", box({-2, -2, 0}, {2, 2, 4}).rotated_z(25, {0, 0, 0}));
  scene.camera = Camera::parallel({0, 0, -1}, {0, 1, 0});
  scene.camera.width = scene.camera.height = 200;
  scene.lights.push_back(Light::directional({-1, -0.5, -0.8}, 0.9));
  return scene;
}

// A thin plate (0.1 thick) floating 0.4 above the ground under the same low light, seen from
// straight above: its shadow on the ground lies about 0.85 units beyond the plate's top along
// every light ray.
Scene thin_plate_scene() {
  Scene scene;
  scene.add("ground", box({-10, -10, -1}, {10, 10, 0}));
  scene.add("plate", box({-3, -3, 0.4}, {3, 3, 0.5}).rotated_z(25, {0, 0, 0}));
  scene.camera = Camera::parallel({0, 0, -1}, {0, 1, 0});
  scene.camera.width = scene.camera.height = 200;
  scene.lights.push_back(Light::directional({-1, -0.5, -0.8}, 0.9));
  return scene;
}

// Light leaking (peter-panning): a large bias pushes the shadow away from the casters' feet,
// so shadowed ground next to them turns lit; a small bias leaks far less.
TEST(RasterShadows, ShadowMapWithALargeBiasLeaksLight) {
  const Scene scene = thin_plate_scene();
  const ShadowResult exact = compute_shadows(scene);
  const ShadowDisagreement small = disagreement(scene, exact, "map:1024:3", 0);
  const ShadowDisagreement large = disagreement(scene, exact, "map:1024:60", 0);
  ASSERT_GT(small.in_shadow, 200);
  EXPECT_LT(small.leaks, small.in_shadow / 50) << "3 texels of bias: the plate's shadow is there";
  EXPECT_GT(large.leaks, small.in_shadow * 9 / 10) << "60 texels (≈ 1.8 units) of bias: the shadow is gone";
}

// Aliasing: shadow edges follow the texels, so a coarse map misjudges a band of ground samples
// along the edges of a rotated block's long shadow, and the band narrows as the resolution grows.
TEST(RasterShadows, ShadowMapAliasingShrinksWithResolution) {
  const Scene scene = low_sun_scene();
  const ShadowResult exact = compute_shadows(scene);
  const ShadowDisagreement coarse = disagreement(scene, exact, "map:64:3", 0);
  const ShadowDisagreement fine = disagreement(scene, exact, "map:1024:3", 0);
  const int wrong_coarse = coarse.leaks + coarse.extra, wrong_fine = fine.leaks + fine.extra;
  EXPECT_GT(wrong_coarse, 100) << "expected blocky edges at 64²";
  EXPECT_LT(5 * wrong_fine, wrong_coarse);
  EXPECT_GT(coarse.compared, 20000);
}

// Several probes per sample estimate the shadowed part of the sample's footprint: partial
// values appear only next to shadow edges, and full or empty ones agree with the exact state.
TEST(RasterShadows, RaysWithSeveralSamplesGivePartialShadowOnlyAtEdges) {
  const Scene scene = shadow_scene();
  const ShadowResult exact = compute_shadows(scene);
  RenderOptions o;
  o.shadows = ShadowSettings::parse("rays:16");
  SampleRecord rec;
  render(scene, o, &rec);
  int partial = 0, full = 0;
  for (size_t i = 0; i < rec.body.size(); ++i) {
    if (rec.body[i] < 0) continue;
    const int c = static_cast<int>(i % rec.columns), r = static_cast<int>(i / rec.columns);
    const Vec3 p = sample_point(rec, c, r);
    // A generous footprint: four pixels at the point's depth (slanted faces stretch it).
    const double footprint = 4 * rec.view.depth(p) / rec.view.scale_x();
    for (int j = 0; j < rec.lights; ++j) {
      const float s = rec.shadow[i * rec.lights + j];
      const FaceShadow& fs = exact.face(j, rec.body[i], rec.face[i]);
      const bool near_edge = fs.to_light == Facing::Front && edge_distance(fs.polygons, p) < footprint;
      if (s > 0 && s < 1) {
        ++partial;
        EXPECT_TRUE(near_edge) << "partial shadow away from edges at " << c << "," << r;
      } else if (!near_edge) {
        ++full;
        const bool expected = fs.to_light != Facing::Front || point_in_polygons(fs.polygons, p);
        EXPECT_EQ(s == 1, expected) << c << "," << r;
      }
    }
  }
  EXPECT_GT(partial, 30);
  EXPECT_GT(full, 10 * partial);
}

// ---- Images ----

TEST(RasterImage, SupersamplingAveragesTheSamples) {
  Scene scene = shadow_scene();
  RenderOptions o;
  o.shadows.method = ShadowSettings::Method::None;  // lighting only
  o.shading = Shading::Flat;
  o.aa = 16;
  SampleRecord rec;
  const Image fine = render(scene, o, &rec);
  o.aa = 1;
  const Image coarse = render(scene, o);
  // Pixels whose 16 samples all show one face equal the single-sample image (flat shading).
  int equal = 0, mixed = 0;
  for (int y = 0; y < fine.height; ++y)
    for (int x = 0; x < fine.width; ++x) {
      std::set<std::pair<int, int>> seen;
      for (int dy = 0; dy < 4; ++dy)
        for (int dx = 0; dx < 4; ++dx) {
          const size_t i = static_cast<size_t>(4 * y + dy) * rec.columns + 4 * x + dx;
          seen.insert({rec.body[i], rec.face[i]});
        }
      if (seen.size() == 1) {
        for (int k = 0; k < 3; ++k) ASSERT_EQ(channel(fine, x, y, k), channel(coarse, x, y, k));
        ++equal;
      } else {
        ++mixed;
      }
    }
  EXPECT_GT(equal, 5000);
  EXPECT_GT(mixed, 200);
}

// Issue 17: tiny and huge but valid scenes. The course's L block on a ground slab, seen in
// perspective under a point light, scaled by s: the cast-shadow area scales as s² and the image
// is the same image (scaling by a power of ten rounds the inputs, so a pixel on an edge may flip:
// at most 1 % of them).
std::string l_block_scene(double s) {
  char text[1024];
  std::snprintf(text, sizeof text, R"({"version": 1, "bodies": [
    {"name": "L", "prism": {"polygon": [[0, 0], [%.17g, 0], [%.17g, %.17g], [%.17g, %.17g], [%.17g, %.17g], [0, %.17g]], "z": [0, %.17g]}},
    {"name": "ground", "box": {"min": [%.17g, %.17g, %.17g], "max": [%.17g, %.17g, 0]}}],
    "camera": {"projection": "perspective", "eye": [%.17g, %.17g, %.17g], "target": [%.17g, %.17g, %.17g], "fov_deg": 40},
    "lights": [{"type": "point", "position": [%.17g, %.17g, %.17g], "intensity": 1}],
    "image": {"width": 80, "height": 60}})",
                4 * s, 4 * s, s, s, s, s, 3 * s, 3 * s, 2 * s, -10 * s, -10 * s, -s, 10 * s, 10 * s,
                -10 * s, -12 * s, 8 * s, s, s, s, 5 * s, -5 * s, 10 * s);
  return text;
}

TEST(RenderExtremes, ScenesFrom1eMinus100To1e100RenderAndCastTheSameShadows) {
  const Scene unit = io::parse_scene("unit.json", l_block_scene(1));
  RenderOptions options;
  options.threads = 1;
  const Image reference = render(unit, options);
  ShadowOptions shadow_options;
  shadow_options.threads = 1;
  const ShadowResult unit_shadows = compute_shadows(unit, shadow_options);
  double unit_area = 0;
  for (const FaceShadow& f : unit_shadows.lights[0].faces) unit_area += f.self_shadowed() ? 0 : f.shadow_area;
  ASSERT_GT(unit_area, 1);
  for (const double s : {1e-100, 1e-30, 1e30, 1e70, 1e100}) {
    SCOPED_TRACE(s);
    const Scene scene = io::parse_scene("scaled.json", l_block_scene(s));
    const Image image = render(scene, options);
    ASSERT_EQ(image.rgb.size(), reference.rgb.size());
    int differ = 0;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) differ += image.pixel(x, y) != reference.pixel(x, y);
    EXPECT_LE(differ, image.width * image.height / 100);
    const ShadowResult shadows = compute_shadows(scene, shadow_options);
    double area = 0;
    for (const FaceShadow& f : shadows.lights[0].faces) area += f.self_shadowed() ? 0 : f.shadow_area;
    EXPECT_NEAR(area / (s * s), unit_area, 1e-9 * unit_area);
  }
}

TEST(RasterImage, PngRoundTripAndAtomicWrite) {
  const fs::path dir = hedra::testing::temp_dir("raster_png");
  Image image;
  image.width = 5;
  image.height = 3;
  for (int i = 0; i < 45; ++i) image.rgb.push_back(static_cast<uint8_t>(i * 5));
  const std::string path = (dir / "a.png").string();
  io::write_png(path, image.width, image.height, image.rgb);
  int w = 0, h = 0;
  EXPECT_EQ(io::read_png(path, &w, &h), image.rgb);
  EXPECT_EQ(w, 5);
  EXPECT_EQ(h, 3);
  EXPECT_THROW(io::write_png((dir / "missing" / "b.png").string(), 5, 3, image.rgb), IoError);
  EXPECT_FALSE(fs::exists(dir / "missing"));
  EXPECT_THROW(io::encode_png(5, 4, image.rgb), InvalidInput);
  std::ofstream(dir / "bad.png") << "not a png";
  EXPECT_THROW(io::read_png((dir / "bad.png").string(), &w, &h), InvalidInput);
  fs::remove_all(dir);
}

// Golden images: small renders compared with tests/golden/*.png, channel by channel, allowing
// small differences (libm, compilers). Regenerate deliberately with HEDRA_UPDATE_GOLDEN=1.
void expect_golden(const std::string& name, const Image& image) {
  const std::string path = std::string(HEDRA_SOURCE_DIR) + "/tests/golden/" + name + ".png";
  if (std::getenv("HEDRA_UPDATE_GOLDEN")) {
    io::write_png(path, image.width, image.height, image.rgb);
    std::printf("wrote %s\n", path.c_str());
    return;
  }
  ASSERT_TRUE(fs::exists(path)) << path << " is missing: run with HEDRA_UPDATE_GOLDEN=1";
  int w = 0, h = 0;
  const std::vector<uint8_t> golden = io::read_png(path, &w, &h);
  ASSERT_EQ(w, image.width);
  ASSERT_EQ(h, image.height);
  int off = 0, far = 0;
  for (size_t i = 0; i < golden.size(); ++i) {
    const int d = std::abs(static_cast<int>(golden[i]) - static_cast<int>(image.rgb[i]));
    off += d > 2;
    far += d > 40;
  }
  // At most 0.5 % of the channels may differ by more than 2 levels, and 0.1 % by more than 40
  // (a sample on a shadow or face boundary decided the other way).
  EXPECT_LE(off, static_cast<int>(golden.size() / 200)) << name;
  EXPECT_LE(far, static_cast<int>(golden.size() / 1000)) << name;
}

TEST(RasterGolden, CityBlockExample) {
  const Scene scene = io::read_scene(std::string(HEDRA_SOURCE_DIR) + "/examples/city-block.json");
  RenderOptions o;
  o.width = 160;
  o.height = 120;
  o.aa = 4;
  o.attenuation = Attenuation::parse("quadratic:1,0.02,0.002");  // the example's four lights saturate without
  o.shadows.method = ShadowSettings::Method::Exact;
  expect_golden("city-block-phong-exact", render(scene, o));
  o.shading = Shading::Gouraud;
  o.shadows = ShadowSettings::parse("map:1024:2");
  expect_golden("city-block-gouraud-map", render(scene, o));
}

TEST(RasterGolden, ShadowSceneFlatRays) {
  RenderOptions o;
  o.shading = Shading::Flat;
  o.shadows = ShadowSettings::parse("rays:4");
  expect_golden("shadow-scene-flat-rays", render(shadow_scene(), o));
}

}  // namespace
}  // namespace hedra
