// Sun studies: the shadows of the sun over a day, step by step, and the hours of direct sun
// per face and per grid point.
#pragma once

#include <string>
#include <vector>

#include "hedra/scene/scene.h"
#include "hedra/scene/sun.h"

namespace hedra {

struct SunStudyOptions {
  double latitude = 0, longitude = 0;  // degrees, north and east positive
  UtcTime start, end;                  // UTC, start <= end
  double step_minutes = 60;            // > 0
  /// Optional grid of sample points on one face: body name, face index, spacing (world units).
  std::string grid_body;
  int grid_face = -1;
  double grid_spacing = 0;
  int threads = 0;
};

/// One time step of a sun study.
struct SunStep {
  UtcTime time;
  double elevation_deg = 0, azimuth_deg = 0;
  bool sun_up = false;  // above the horizon; below it every face is unlit (fraction 0)
  /// Lit fraction of every face (ShadowResult::first_face indexing): 0 for self-shadowed and
  /// grazing faces and at night, 1 − shadow_area / area otherwise.
  std::vector<double> lit_fraction;
};

struct SunStudy {
  std::vector<SunStep> steps;
  /// Hours of direct sun per face: the trapezoid rule over the steps' lit fractions.
  std::vector<double> sun_hours;
  std::vector<int> first_face;  // as ShadowResult::first_face
  /// The optional grid: sample points (on the face, inside it) and their hours of direct sun
  /// (each point lit or not at each step, decided exactly by in_shadow's test).
  std::vector<Vec3> grid_points;
  std::vector<double> grid_hours;
};

/// The sun over a day: shadows at start, start + step, …, and at end.
/// \throw InvalidInput for a bad place, times out of order, a step <= 0, more than 10000
///   steps, or a grid body/face that does not exist.
SunStudy sun_study(const Scene& scene, const SunStudyOptions& options);

}  // namespace hedra
