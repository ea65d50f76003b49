// Progress and cancellation (hedra/core/progress.h): each long pass reports fractions that
// rise to 1 on the calling thread, and a callback returning false stops it with the typed
// error hedra::Cancelled (DecompositionCancelled for a decomposition) and no result.
#include "hedra/core/progress.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "hedra/core/primitives.h"
#include "hedra/decompose/decompose.h"
#include "hedra/render/raster.h"
#include "hedra/scene/scene.h"
#include "hedra/visibility/roberts.h"
#include "hedra/visibility/shadows.h"

namespace hedra {
namespace {

// Boxes on a ground slab, lit by one light, seen in perspective.
Scene test_scene() {
  Scene s;
  s.add("ground", box({-10, -10, -1}, {10, 10, 0}));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      s.add("b" + std::to_string(i) + std::to_string(j),
            box({-8.0 + 4 * i, -8.0 + 4 * j, 0}, {-6.5 + 4 * i, -6.0 + 4 * j, 1.0 + i + j}));
  s.lights.push_back(Light::directional({-1, -0.5, -2}));
  s.camera = Camera::perspective({25, -30, 20}, {0, 0, 0}, 40);
  s.camera.width = 160;
  s.camera.height = 120;
  return s;
}

// A callback that records what it is told and cancels at call `stop` (never when 0), or at the
// first fraction above `above`.
struct Recorder {
  std::vector<double> seen;
  int stop = 0;
  double above = 2;
  std::thread::id caller = std::this_thread::get_id();
  bool other_thread = false;
  ProgressCallback callback() {
    return [this](double f) {
      seen.push_back(f);
      other_thread = other_thread || std::this_thread::get_id() != caller;
      if (f > above) return false;
      return stop == 0 || static_cast<int>(seen.size()) < stop;
    };
  }
  void expect_complete() const {
    ASSERT_FALSE(seen.empty());
    EXPECT_FALSE(other_thread);
    for (size_t i = 1; i < seen.size(); ++i) EXPECT_LE(seen[i - 1], seen[i]);
    EXPECT_GE(seen.front(), 0.0);
    EXPECT_DOUBLE_EQ(seen.back(), 1.0);
  }
};

TEST(Progress, HiddenLinesReportAndCancel) {
  const Scene scene = test_scene();
  Recorder full;
  HlrOptions o;
  o.progress = full.callback();
  const HlrResult reference = hidden_lines(scene);
  const HlrResult r = hidden_lines(scene, o);
  full.expect_complete();
  EXPECT_EQ(r.visible.size(), reference.visible.size());  // reporting changes nothing
  Recorder cancel;
  cancel.stop = 1;
  o.progress = cancel.callback();
  EXPECT_THROW(hidden_lines(scene, o), Cancelled);
  EXPECT_EQ(cancel.seen.size(), 1u);  // stopped at once
}

TEST(Progress, ShadowsReportAndCancel) {
  const Scene scene = test_scene();
  Recorder full;
  ShadowOptions o;
  o.visible_parts = true;
  o.progress = full.callback();
  const ShadowResult r = compute_shadows(scene, o);
  full.expect_complete();
  EXPECT_EQ(r.lights.size(), 1u);
  Recorder cancel;
  cancel.stop = 2;
  o.progress = cancel.callback();
  try {
    compute_shadows(scene, o);
    FAIL() << "not cancelled";
  } catch (const Cancelled& e) {
    EXPECT_STREQ(e.what(), "shadows cancelled");
  }
  EXPECT_EQ(cancel.seen.size(), 2u);
}

TEST(Progress, RenderingReportsAndCancels) {
  const Scene scene = test_scene();
  RenderOptions o;
  Recorder full;
  o.progress = full.callback();
  const Image with = render(scene, o);
  full.expect_complete();
  o.progress = nullptr;
  EXPECT_EQ(with.rgb, render(scene, o).rgb);  // reporting changes nothing
  // Cancelled during the exact shadow polygons (their reports map to 0.05 … 0.5; their last
  // stage always reports) and during the tiles (0.5 … 1; the last always reports).
  for (double above : {0.06, 0.5}) {
    Recorder cancel;
    cancel.above = above;
    o.progress = cancel.callback();
    Image image;
    EXPECT_THROW(image = render(scene, o), Cancelled) << above;
    EXPECT_TRUE(image.rgb.empty());  // no partial image
    ASSERT_FALSE(cancel.seen.empty());
    EXPECT_LE(cancel.seen.back(), above == 0.06 ? 0.5 : 1.0);  // stopped in that stage
  }
}

TEST(Progress, DecompositionCancelledIsACancelled) {
  // An L prism is not convex: its decomposition reports and can be stopped.
  const Body l = prism({{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 1);
  DecomposeOptions o;
  o.progress = [](int, int) { return false; };
  EXPECT_THROW(decompose(l, o), DecompositionCancelled);
  EXPECT_THROW(decompose(l, o), Cancelled);
}

TEST(Progress, MeterWithoutCallbackNeverCancels) {
  ProgressMeter m(nullptr);
  m.stage(0, 1, 10);
  for (int i = 0; i < 100; ++i) m.add();
  m.finish_stage();
  m.check();
  EXPECT_FALSE(m.active());
}

}  // namespace
}  // namespace hedra
