// Sun studies in slices: slices computed apart and joined by combine_sun_studies equal the
// whole study bit for bit (the reference: sun_study over the whole schedule, computed once).
#include "hedra/visibility/sun_study.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "hedra/core/error.h"
#include "hedra/core/primitives.h"
#include "hedra/visibility/shadows.h"

namespace hedra {
namespace {

// A small city: a ground slab, a 4 × 4 grid of towers of several heights, one L-shaped
// (non-convex) block among them.
Scene city() {
  Scene s;
  s.add("ground", box({-12, -12, -1}, {12, 12, 0}));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      s.add("t" + std::to_string(i) + std::to_string(j),
            box({-9.0 + 5 * i, -9.0 + 5 * j, 0},
                {-7.0 + 5 * i, -7.5 + 5 * j, 2.0 + (i * 7 + j * 3) % 5}));
  // An L at the crossing of the middle streets, counter-clockwise.
  s.add("block",
        prism({{-1.5, -1.5}, {0.5, -1.5}, {0.5, -0.5}, {-0.5, -0.5}, {-0.5, 0.5}, {-1.5, 0.5}}, 0,
              3.5));
  return s;
}

SunStudyOptions day() {
  SunStudyOptions o;
  o.latitude = 48.85;
  o.longitude = 2.35;
  o.start = UtcTime::parse("2026-03-20T04:10:00Z");
  o.end = UtcTime::parse("2026-03-20T19:45:00Z");  // not on a step: one more step at the end
  o.step_minutes = 45;
  o.grid_body = "ground";
  o.grid_face = 5;  // z = 0, the top
  o.grid_spacing = 2.5;
  return o;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_identical(const SunStudy& a, const SunStudy& b) {
  ASSERT_EQ(a.steps.size(), b.steps.size());
  EXPECT_EQ(a.first_step, b.first_step);
  EXPECT_EQ(a.first_face, b.first_face);
  EXPECT_EQ(a.grid_points, b.grid_points);
  for (size_t k = 0; k < a.steps.size(); ++k) {
    const SunStep &x = a.steps[k], &y = b.steps[k];
    EXPECT_EQ(x.time.to_string(), y.time.to_string()) << "step " << k;
    EXPECT_TRUE(same_bits(x.elevation_deg, y.elevation_deg)) << "step " << k;
    EXPECT_TRUE(same_bits(x.azimuth_deg, y.azimuth_deg)) << "step " << k;
    EXPECT_EQ(x.sun_up, y.sun_up) << "step " << k;
    ASSERT_EQ(x.lit_fraction.size(), y.lit_fraction.size());
    for (size_t i = 0; i < x.lit_fraction.size(); ++i)
      EXPECT_TRUE(same_bits(x.lit_fraction[i], y.lit_fraction[i])) << "step " << k << " face " << i;
    EXPECT_EQ(x.grid_lit, y.grid_lit) << "step " << k;
  }
  ASSERT_EQ(a.sun_hours.size(), b.sun_hours.size());
  for (size_t i = 0; i < a.sun_hours.size(); ++i)
    EXPECT_TRUE(same_bits(a.sun_hours[i], b.sun_hours[i]))
        << "face " << i << ": " << a.sun_hours[i] << " vs " << b.sun_hours[i];
  ASSERT_EQ(a.grid_hours.size(), b.grid_hours.size());
  for (size_t g = 0; g < a.grid_hours.size(); ++g)
    EXPECT_TRUE(same_bits(a.grid_hours[g], b.grid_hours[g])) << "grid point " << g;
}

SunStudy slice(const Scene& scene, SunStudyOptions o, int first, int count) {
  o.first_step = first;
  o.step_count = count;
  return sun_study(scene, o);
}

TEST(SunStudySlices, CombinedSlicesEqualTheWholeStudyBitForBit) {
  const Scene scene = city();
  const SunStudyOptions whole = day();
  const int n = sun_study_steps(whole);
  // 04:10 … 19:10 every 45 min is 21 steps, and 19:45 one more.
  ASSERT_EQ(n, 22);
  const SunStudy reference = sun_study(scene, whole);
  ASSERT_EQ(reference.steps.size(), static_cast<size_t>(n));
  ASSERT_GT(reference.grid_points.size(), 50u);
  // The study is not trivial: the sun rises and sets, faces and grid points are partly lit.
  EXPECT_FALSE(reference.steps.front().sun_up);
  EXPECT_TRUE(reference.steps[static_cast<size_t>(n / 2)].sun_up);
  double least = 1e9, most = 0;
  for (double h : reference.grid_hours) least = std::min(least, h), most = std::max(most, h);
  EXPECT_LT(least, most - 1);

  // Two slices at several places, three slices, one step per slice.
  for (int k : {1, 7, 11, n - 1}) {
    SCOPED_TRACE("split at step " + std::to_string(k));
    expect_identical(combine_sun_studies({slice(scene, whole, 0, k), slice(scene, whole, k, n - k)},
                                         whole),
                     reference);
  }
  expect_identical(combine_sun_studies({slice(scene, whole, 0, 5), slice(scene, whole, 5, 9),
                                        slice(scene, whole, 14, -1)},
                                       whole),
                   reference);
  std::vector<SunStudy> singles;
  for (int k = 0; k < n; ++k) singles.push_back(slice(scene, whole, k, 1));
  expect_identical(combine_sun_studies(singles, whole), reference);
  // An empty slice joins as nothing.
  expect_identical(combine_sun_studies({slice(scene, whole, 0, 10), slice(scene, whole, 10, 0),
                                        slice(scene, whole, 10, -1)},
                                       whole),
                   reference);
}

TEST(SunStudySlices, SlicesMustCoverTheScheduleInOrder) {
  const Scene scene = city();
  const SunStudyOptions whole = day();
  const int n = sun_study_steps(whole);
  const SunStudy a = slice(scene, whole, 0, 4), b = slice(scene, whole, 4, -1);
  EXPECT_THROW(combine_sun_studies({b, a}, whole), InvalidInput);          // out of order
  EXPECT_THROW(combine_sun_studies({a}, whole), InvalidInput);             // not all of it
  EXPECT_THROW(combine_sun_studies({a, a, b}, whole), InvalidInput);       // repeated
  EXPECT_THROW(slice(scene, whole, n + 1, -1), InvalidInput);              // beyond the end
  EXPECT_THROW(slice(scene, whole, 3, n), InvalidInput);                   // runs past the end
  EXPECT_THROW(slice(scene, whole, -1, 2), InvalidInput);
  // A slice's own hours integrate over its own steps only.
  const SunStudy tail = slice(scene, whole, n - 2, 2);
  ASSERT_EQ(tail.steps.size(), 2u);
  EXPECT_EQ(tail.first_step, n - 2);
}

TEST(SunStudySlices, StepCountFollowsTheSchedule) {
  SunStudyOptions o = day();
  o.start = UtcTime::parse("2026-06-21T06:00:00Z");
  o.end = UtcTime::parse("2026-06-21T08:00:00Z");
  o.step_minutes = 30;
  EXPECT_EQ(sun_study_steps(o), 5);  // 6:00, 6:30, 7:00, 7:30, 8:00
  o.end = UtcTime::parse("2026-06-21T08:10:00Z");
  EXPECT_EQ(sun_study_steps(o), 6);  // and 8:10
  o.step_minutes = 0;
  EXPECT_THROW(sun_study_steps(o), InvalidInput);
}

}  // namespace
}  // namespace hedra
