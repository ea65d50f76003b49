// The hidden-line SVG: fitting, classes, stroke widths in pixels, round caps, dashes.
#include "hedra/render/svg.h"

#include <gtest/gtest.h>

#include <regex>

#include "hedra/core/primitives.h"
#include "hedra/render/raster.h"
#include "hedra/scene/scene.h"

namespace hedra {
namespace {

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Every coordinate of the path data, in order.
std::vector<double> coordinates(const std::string& svg) {
  std::vector<double> out;
  const std::regex path(" d=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), path); it != std::sregex_iterator(); ++it) {
    const std::string d = (*it)[1];
    const std::regex number("-?[0-9]+(\\.[0-9]+)?");
    for (auto n = std::sregex_iterator(d.begin(), d.end(), number); n != std::sregex_iterator(); ++n)
      out.push_back(std::stod(n->str()));
  }
  return out;
}

TEST(Svg, FitsTheBoxWithTheMargin) {
  const PictureFit fit = fit_picture(Eigen::AlignedBox2d(Vec2(0, 0), Vec2(10, 5)), 800, 600, 0.05);
  EXPECT_DOUBLE_EQ(fit.scale, 72);  // min(720 / 10, 540 / 5)
  EXPECT_TRUE(fit.to_pixels({0, 0}).isApprox(Vec2(40, 480)));
  EXPECT_TRUE(fit.to_pixels({10, 5}).isApprox(Vec2(760, 120)));  // y runs down
}

TEST(Svg, DrawsClassesWithPixelStrokesAndRoundCaps) {
  const std::vector<Body> bodies{box({0, 0, 0}, {4, 4, 4}), box({-1, 1, 1}, {5, 3, 3})};
  HlrOptions o;
  o.hidden = true;
  const HlrResult r = hidden_lines(bodies, Camera::parallel({1, 0.5, -0.7}), o);
  SvgStyle style;
  style.width = 640;
  style.height = 480;
  style.hidden = true;
  const std::string svg = hidden_lines_svg(r, style);
  EXPECT_NE(svg.find("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"640\" height=\"480\""), std::string::npos);
  EXPECT_EQ(count(svg, "<g class=\"visible\""), 1);
  EXPECT_EQ(count(svg, "<g class=\"junction\""), 1);
  EXPECT_EQ(count(svg, "<g class=\"hidden\""), 1);
  EXPECT_EQ(count(svg, "stroke-linecap=\"round\""), 3);
  EXPECT_NE(svg.find("stroke-dasharray=\"4 3\""), std::string::npos);
  EXPECT_NE(svg.find("vector-effect: non-scaling-stroke"), std::string::npos);
  // One "M" per segment: visible edges, junctions, hidden.
  EXPECT_EQ(count(svg, "M"), static_cast<int>(r.visible.size() + r.hidden.size()));
  // Everything inside the image less the 5 % margin (32 px, 24 px), touching it on one axis.
  const std::vector<double> c = coordinates(svg);
  double xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
  for (size_t i = 0; i + 1 < c.size(); i += 2) {
    xmin = std::min(xmin, c[i]), xmax = std::max(xmax, c[i]);
    ymin = std::min(ymin, c[i + 1]), ymax = std::max(ymax, c[i + 1]);
  }
  EXPECT_GE(xmin, 32 - 0.01);
  EXPECT_LE(xmax, 608 + 0.01);
  EXPECT_GE(ymin, 24 - 0.01);
  EXPECT_LE(ymax, 456 + 0.01);
  EXPECT_TRUE(std::abs(xmin - 32) < 0.02 || std::abs(ymin - 24) < 0.02);
  // Without --hidden: no dashed group.
  style.hidden = false;
  EXPECT_EQ(hidden_lines_svg(r, style).find("class=\"hidden\""), std::string::npos);
}

TEST(Svg, StrokeWidthDoesNotDependOnTheSceneScale) {
  const std::vector<Body> small{box({0, 0, 0}, {1, 2, 3})};
  const std::vector<Body> large{box({0, 0, 0}, {1000, 2000, 3000})};
  const Camera camera = Camera::parallel({-1, -2, -3});
  SvgStyle style;
  const std::string a = hidden_lines_svg(hidden_lines(small, camera), style);
  const std::string b = hidden_lines_svg(hidden_lines(large, camera), style);
  EXPECT_EQ(a, b);  // same picture, same pixels, same strokes
  EXPECT_NE(a.find("stroke-width=\"1.5\""), std::string::npos);
}

// Framed by the scene's view (the default of `hlr -o`), every point of the drawing lands where
// render() puts it: the view render() reports in its SampleRecord, to 1e-6 px, for a parallel
// and a perspective camera; the document holds those points to its 0.01 px.
TEST(Svg, FramesTheDrawingAsTheRendererFramesTheScene) {
  for (const Camera& camera : {Camera::parallel({1, 0.5, -0.7}), Camera::perspective({9, -7, 6}, {1, 1, 1}, 50)}) {
    Scene scene;
    scene.add("cube", box({0, 0, 0}, {4, 4, 4}));
    scene.add("bar", box({-1, 1, 1}, {5, 3, 3}));
    scene.camera = camera;
    scene.camera.width = 320;
    scene.camera.height = 200;
    SampleRecord record;
    RenderOptions ro;
    ro.shadows.method = ShadowSettings::Method::None;
    render(scene, ro, &record);
    const HlrResult r = hidden_lines(scene);
    SvgStyle style;
    style.width = 320;
    style.height = 200;
    style.view = scene_view(scene, 320, 200);
    const SvgFrame frame(style, r);
    for (const SceneBody& b : scene.bodies())
      for (const Vec3& v : b.body.vertices()) {
        const Eigen::Vector2d expected = record.view.project(v);
        const Vec2 got = frame.pixels(v, Vec2::Zero());
        EXPECT_NEAR(got.x(), expected.x(), 1e-6);
        EXPECT_NEAR(got.y(), expected.y(), 1e-6);
      }
    // The path data: each visible segment's ends, in order, at the render's pixels.
    const std::string svg = hidden_lines_svg(r, style);
    const std::vector<double> c = coordinates(svg);
    ASSERT_EQ(c.size(), 4 * r.visible.size());
    std::vector<const HlrSegment*> order;
    for (LineKind kind : {LineKind::Edge, LineKind::Junction})
      for (const HlrSegment& s : r.visible)
        if (s.kind == kind) order.push_back(&s);
    for (size_t i = 0; i < order.size(); ++i) {
      const Eigen::Vector2d a = record.view.project(order[i]->a), b = record.view.project(order[i]->b);
      EXPECT_NEAR(c[4 * i], a.x(), 0.0051);
      EXPECT_NEAR(c[4 * i + 1], a.y(), 0.0051);
      EXPECT_NEAR(c[4 * i + 2], b.x(), 0.0051);
      EXPECT_NEAR(c[4 * i + 3], b.y(), 0.0051);
    }
  }
}

}  // namespace
}  // namespace hedra
