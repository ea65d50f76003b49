#include "hedra/scene/sun.h"

#include <gtest/gtest.h>

#include "hedra/core/error.h"
#include "hedra/scene/light.h"

namespace hedra {
namespace {

// Reference: NREL's Solar Position Algorithm report (Reda & Andreas, NREL/TP-560-34302, 2004),
// table A5.1: 2003-10-17 12:30:30 local time (UTC−7), latitude 39.742476, longitude −105.1786:
// topocentric zenith 50.11162° (refracted for 820 mbar, 11 °C), azimuth 194.34024°, equation
// of time 14.641503 min, geocentric declination −9.31434°. NOAA's algorithm with its standard
// refraction agrees to 0.01° (the refraction models differ by ~0.004° at this elevation).
TEST(Sun, AgreesWithNrelSpaExample) {
  SunPosition s = sun_position(39.742476, -105.1786, UtcTime::parse("2003-10-17T19:30:30Z"));
  EXPECT_NEAR(90 - s.elevation_deg, 50.11162, 0.01);
  EXPECT_NEAR(s.azimuth_deg, 194.34024, 0.01);
  EXPECT_NEAR(s.equation_of_time_min, 14.641503, 0.01);
  EXPECT_NEAR(s.declination_deg, -9.31434, 0.002);
}

TEST(Sun, SolsticesAndEquinoxes) {
  // Declination ±23.44° at the 2026 solstices (June 21 08:24 UTC, December 21 20:50 UTC),
  // ~0 at the equinoxes (March 20 14:46 UTC, September 23 00:05 UTC) — USNO dates.
  EXPECT_NEAR(sun_position(0, 0, UtcTime::parse("2026-06-21T08:24:00Z")).declination_deg, 23.44, 0.01);
  EXPECT_NEAR(sun_position(0, 0, UtcTime::parse("2026-12-21T20:50:00Z")).declination_deg, -23.44, 0.01);
  EXPECT_NEAR(sun_position(0, 0, UtcTime::parse("2026-03-20T14:46:00Z")).declination_deg, 0, 0.01);
  EXPECT_NEAR(sun_position(0, 0, UtcTime::parse("2026-09-23T00:05:00Z")).declination_deg, 0, 0.01);
}

TEST(Sun, NoonInBerlinAtMidsummer) {
  // Solar noon in Berlin (13.40° E) on 2026-06-21: 12:00 − 13.40·4 min − EoT(−1.8 min) ≈ 11:08 UTC;
  // elevation 90 − 52.52 + 23.44 = 60.92° (+ refraction 0.01°), sun due south.
  SunPosition s = sun_position(52.52, 13.40, UtcTime::parse("2026-06-21T11:08:00Z"));
  EXPECT_NEAR(s.elevation_deg, 60.93, 0.02);
  EXPECT_NEAR(s.azimuth_deg, 180, 0.3);
  EXPECT_GT(s.towards_sun.z(), 0.87);
  EXPECT_LT(s.towards_sun.y(), 0);  // south is −y
}

TEST(Sun, RefusesNight) {
  try {
    sunlight_direction(52.52, 13.40, UtcTime::parse("2026-06-21T23:00:00Z"));
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("the sun is below the horizon at latitude 52.52"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(Light::sun(52.52, 13.40, UtcTime::parse("2026-12-21T16:00:00Z")), InvalidInput);
}

TEST(Sun, TimeParsing) {
  UtcTime t = UtcTime::parse("2026-06-21T10:00:00Z");
  EXPECT_EQ(t.to_string(), "2026-06-21T10:00:00Z");
  EXPECT_EQ(UtcTime::parse("2026-06-21T10:00Z").to_string(), "2026-06-21T10:00:00Z");
  EXPECT_DOUBLE_EQ(UtcTime::parse("2000-01-01T12:00:00Z").julian_day(), 2451545.0);
  EXPECT_THROW(UtcTime::parse("2026-06-21 10:00"), InvalidInput);
  EXPECT_THROW(UtcTime::parse("2026-06-21T10:00:00+02:00"), InvalidInput);
  EXPECT_THROW(UtcTime::parse("2026-02-30T10:00:00Z"), InvalidInput);
  EXPECT_THROW(sun_position(91, 0, t), InvalidInput);
}

}  // namespace
}  // namespace hedra
