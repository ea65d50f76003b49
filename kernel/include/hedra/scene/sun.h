// Solar position: the sun as a directional light for a place and a UTC time.
#pragma once

#include <string>

#include "hedra/core/plane.h"

namespace hedra {

/// A UTC instant, from an ISO 8601 string "YYYY-MM-DDThh:mm[:ss[.fff]]Z" (the Z, or +00:00,
/// is required: times are UTC).
struct UtcTime {
  int year = 2000, month = 1, day = 1, hour = 12, minute = 0;
  double second = 0;
  /// \throw InvalidInput naming the text and what is wrong.
  static UtcTime parse(const std::string& iso8601);
  std::string to_string() const;  // ISO 8601 with Z
  double julian_day() const;
};

struct SunPosition {
  double azimuth_deg = 0;    // clockwise from north
  double elevation_deg = 0;  // above the horizon, corrected for standard atmospheric refraction
  double declination_deg = 0;
  double equation_of_time_min = 0;
  /// Unit vector from the ground towards the sun in hedra's world frame:
  /// x = east, y = north, z = up.
  Vec3 towards_sun = Vec3::UnitZ();
};

/// The NOAA solar position algorithm (the NOAA Global Monitoring Laboratory's solar
/// calculator spreadsheet, after Meeus, "Astronomical Algorithms"), with NOAA's refraction
/// correction. Valid for 1901–2099; tests/scene/sun_test.cpp checks it against NREL's SPA reference
/// example (Reda & Andreas 2004) to 0.02° and against the solstice/equinox declinations.
/// latitude in [−90, 90] (north positive), longitude in [−180, 180] (east positive).
/// \throw InvalidInput for latitudes/longitudes out of range or non-finite.
SunPosition sun_position(double latitude_deg, double longitude_deg, const UtcTime& time);

/// Direction the sunlight travels (−towards_sun).
/// \throw InvalidInput "the sun is below the horizon at … (elevation −12.3°)" at night.
Vec3 sunlight_direction(double latitude_deg, double longitude_deg, const UtcTime& time);

}  // namespace hedra
