#include "hedra/scene/sun.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "hedra/core/error.h"

namespace hedra {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

double wrap360(double x) {
  x = std::fmod(x, 360.0);
  return x < 0 ? x + 360 : x;
}

bool leap(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

}  // namespace

UtcTime UtcTime::parse(const std::string& s) {
  UtcTime t;
  int n = 0;
  int matched = std::sscanf(s.c_str(), "%4d-%2d-%2dT%2d:%2d%n", &t.year, &t.month, &t.day, &t.hour,
                            &t.minute, &n);
  if (matched != 5)
    throw InvalidInput("time '" + s + "' is not ISO 8601 (expected YYYY-MM-DDThh:mm:ssZ)");
  std::string rest = s.substr(n);
  if (!rest.empty() && rest[0] == ':') {
    size_t used = 0;
    try {
      t.second = std::stod(rest.substr(1), &used);
    } catch (const std::exception&) {
      throw InvalidInput("time '" + s + "': bad seconds");
    }
    rest = rest.substr(1 + used);
  }
  if (rest != "Z" && rest != "+00:00")
    throw InvalidInput("time '" + s + "' must be UTC (end with Z)");
  static const int days[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  if (t.month < 1 || t.month > 12) throw InvalidInput("time '" + s + "': month out of range");
  const int dmax = days[t.month - 1] + (t.month == 2 && leap(t.year));
  if (t.day < 1 || t.day > dmax) throw InvalidInput("time '" + s + "': day out of range");
  if (t.hour < 0 || t.hour > 23 || t.minute < 0 || t.minute > 59 || !(t.second >= 0) ||
      t.second >= 61)
    throw InvalidInput("time '" + s + "': time of day out of range");
  if (t.year < 1901 || t.year > 2099)
    throw InvalidInput("time '" + s + "': the solar algorithm is valid for 1901–2099");
  return t;
}

std::string UtcTime::to_string() const {
  char buf[48];
  if (second == std::floor(second))
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02dZ", year, month, day, hour, minute,
                  static_cast<int>(second));
  else
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%09.6fZ", year, month, day, hour,
                  minute, second);
  return buf;
}

double UtcTime::julian_day() const {
  // Meeus, chapter 7 (Gregorian calendar).
  int y = year, m = month;
  if (m <= 2) { y -= 1; m += 12; }
  const int a = y / 100, b = 2 - a + a / 4;
  const double day_fraction = (hour + (minute + second / 60.0) / 60.0) / 24.0;
  return std::floor(365.25 * (y + 4716)) + std::floor(30.6001 * (m + 1)) + day + day_fraction + b -
         1524.5;
}

SunPosition sun_position(double latitude, double longitude, const UtcTime& time) {
  if (!std::isfinite(latitude) || latitude < -90 || latitude > 90)
    throw InvalidInput("latitude must lie in [-90, 90]");
  if (!std::isfinite(longitude) || longitude < -180 || longitude > 180)
    throw InvalidInput("longitude must lie in [-180, 180]");
  // The NOAA spreadsheet, step by step (angles in degrees unless noted).
  const double jd = time.julian_day();
  const double t = (jd - 2451545.0) / 36525.0;  // Julian century
  const double l0 = wrap360(280.46646 + t * (36000.76983 + t * 0.0003032));
  const double m = 357.52911 + t * (35999.05029 - 0.0001537 * t);
  const double e = 0.016708634 - t * (0.000042037 + 0.0000001267 * t);
  const double c = std::sin(m * kDeg) * (1.914602 - t * (0.004817 + 0.000014 * t)) +
                   std::sin(2 * m * kDeg) * (0.019993 - 0.000101 * t) +
                   std::sin(3 * m * kDeg) * 0.000289;
  const double true_long = l0 + c;
  const double omega = 125.04 - 1934.136 * t;
  const double app_long = true_long - 0.00569 - 0.00478 * std::sin(omega * kDeg);
  const double eps0 =
      23 + (26 + (21.448 - t * (46.815 + t * (0.00059 - t * 0.001813))) / 60) / 60;
  const double eps = eps0 + 0.00256 * std::cos(omega * kDeg);
  const double decl = std::asin(std::sin(eps * kDeg) * std::sin(app_long * kDeg)) / kDeg;
  const double y = std::pow(std::tan(eps / 2 * kDeg), 2);
  const double eot =
      4 / kDeg *
      (y * std::sin(2 * l0 * kDeg) - 2 * e * std::sin(m * kDeg) +
       4 * e * y * std::sin(m * kDeg) * std::cos(2 * l0 * kDeg) -
       0.5 * y * y * std::sin(4 * l0 * kDeg) - 1.25 * e * e * std::sin(2 * m * kDeg));
  const double minutes = time.hour * 60 + time.minute + time.second / 60;
  const double true_solar = std::fmod(minutes + eot + 4 * longitude + 1440 * 4, 1440.0);
  double hour_angle = true_solar / 4 < 0 ? true_solar / 4 + 180 : true_solar / 4 - 180;
  const double lat = latitude * kDeg, dec = decl * kDeg, ha = hour_angle * kDeg;
  double cos_zenith = std::sin(lat) * std::sin(dec) + std::cos(lat) * std::cos(dec) * std::cos(ha);
  cos_zenith = std::clamp(cos_zenith, -1.0, 1.0);
  const double zenith = std::acos(cos_zenith) / kDeg;
  // Azimuth clockwise from north.
  double azimuth;
  const double denominator = std::cos(lat) * std::sin(zenith * kDeg);
  if (std::abs(denominator) < 1e-12) {
    azimuth = latitude > 0 ? 180 : 0;
  } else {
    double a = (std::sin(lat) * cos_zenith - std::sin(dec)) / denominator;
    a = std::acos(std::clamp(a, -1.0, 1.0)) / kDeg;
    azimuth = hour_angle > 0 ? wrap360(a + 180) : wrap360(540 - a);
  }
  // NOAA's refraction correction (degrees), by elevation band.
  const double h = 90 - zenith;
  double refraction = 0;
  if (h <= 85) {
    const double te = std::tan(h * kDeg);
    if (h > 5)
      refraction = 58.1 / te - 0.07 / (te * te * te) + 0.000086 / std::pow(te, 5);
    else if (h > -0.575)
      refraction = 1735 + h * (-518.2 + h * (103.4 + h * (-12.79 + h * 0.711)));
    else
      refraction = -20.772 / te;
    refraction /= 3600;
  }
  SunPosition s;
  s.azimuth_deg = azimuth;
  s.elevation_deg = h + refraction;
  s.declination_deg = decl;
  s.equation_of_time_min = eot;
  const double el = s.elevation_deg * kDeg, az = azimuth * kDeg;
  s.towards_sun = Vec3(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el));
  return s;
}

Vec3 sunlight_direction(double latitude, double longitude, const UtcTime& time) {
  SunPosition s = sun_position(latitude, longitude, time);
  if (s.elevation_deg <= 0) {
    char buf[160];
    std::snprintf(buf, sizeof buf,
                  "the sun is below the horizon at latitude %g, longitude %g, %s (elevation %.1f°)",
                  latitude, longitude, time.to_string().c_str(), s.elevation_deg);
    throw InvalidInput(buf);
  }
  return -s.towards_sun;
}

// ---- Calendar ----

namespace {

// Days from 1970-01-01 to y-m-d (proleptic Gregorian; H. Hinnant's algorithm).
int64_t days_from_civil(int64_t y, unsigned m, unsigned d) {
  y -= m <= 2;
  const int64_t era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<int64_t>(doe) - 719468;
}

void civil_from_days(int64_t z, int& y, int& m, int& d) {
  z += 719468;
  const int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const unsigned doe = static_cast<unsigned>(z - era * 146097);
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  d = static_cast<int>(doy - (153 * mp + 2) / 5 + 1);
  m = static_cast<int>(mp < 10 ? mp + 3 : mp - 9);
  y = static_cast<int>(static_cast<int64_t>(yoe) + era * 400 + (m <= 2));
}

double seconds_of(const UtcTime& t) {
  return static_cast<double>(days_from_civil(t.year, static_cast<unsigned>(t.month),
                                             static_cast<unsigned>(t.day))) *
             86400.0 +
         t.hour * 3600.0 + t.minute * 60.0 + t.second;
}

}  // namespace

double minutes_between(const UtcTime& a, const UtcTime& b) {
  return (seconds_of(b) - seconds_of(a)) / 60;
}

UtcTime add_minutes(const UtcTime& t, double minutes) {
  const double s = seconds_of(t) + minutes * 60;
  const double day = std::floor(s / 86400);
  double rest = s - day * 86400;
  UtcTime out;
  civil_from_days(static_cast<int64_t>(day), out.year, out.month, out.day);
  // Round to the millisecond so that steps of whole minutes stay whole.
  rest = std::round(rest * 1000) / 1000;
  if (rest >= 86400) rest = 86399.999;
  out.hour = static_cast<int>(rest / 3600);
  rest -= out.hour * 3600.0;
  out.minute = static_cast<int>(rest / 60);
  out.second = rest - out.minute * 60.0;
  if (out.second < 0) out.second = 0;
  return out;
}

}  // namespace hedra
