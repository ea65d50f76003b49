// Sun studies: the shadows of the sun over a day, step by step, and the hours of direct sun
// per face and per grid point. A study may be computed in slices of its schedule (apart, in
// parallel or on other machines) and joined exactly (combine_sun_studies).
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
  /// A contiguous slice of the schedule start, start + step, …, end (sun_study_steps() steps
  /// in all, numbered from 0): steps first_step … first_step + step_count − 1; step_count −1
  /// means to the end. Slices computed apart (other threads, processes or machines) give
  /// exactly the steps of the whole study; combine_sun_studies joins them.
  int first_step = 0;
  int step_count = -1;
};

/// One time step of a sun study.
struct SunStep {
  UtcTime time;
  double elevation_deg = 0, azimuth_deg = 0;
  bool sun_up = false;  // above the horizon; below it every face is unlit (fraction 0)
  /// Lit fraction of every face (ShadowResult::first_face indexing): 0 for self-shadowed and
  /// grazing faces and at night, 1 − shadow_area / area otherwise.
  std::vector<double> lit_fraction;
  /// The grid points lit (1) or not (0) at this step, SunStudy::grid_points order; empty
  /// without a grid.
  std::vector<char> grid_lit;
};

struct SunStudy {
  /// The steps of the slice computed, in order; steps[k] is step first_step + k of the whole
  /// schedule.
  std::vector<SunStep> steps;
  int first_step = 0;
  /// Hours of direct sun per face: the trapezoid rule over the steps' lit fractions.
  std::vector<double> sun_hours;
  std::vector<int> first_face;  // as ShadowResult::first_face
  /// The optional grid: sample points (on the face, inside it) and their hours of direct sun
  /// (each point lit or not at each step, decided exactly by in_shadow's test).
  std::vector<Vec3> grid_points;
  std::vector<double> grid_hours;
};

/// The sun over a day: shadows at start, start + step, …, and at end (the steps of the slice
/// options.first_step, options.step_count; sun_hours and grid_hours integrate over the
/// slice's own steps, by combine_sun_studies' rule, the whole day by default).
/// \throw InvalidInput for a bad place, times out of order, a step <= 0, more than 10000
///   steps, a slice outside the schedule, or a grid body/face that does not exist.
/// Cost: one shadow computation (compute_shadows without polygons) per step of the slice.
SunStudy sun_study(const Scene& scene, const SunStudyOptions& options);

/// The number of steps of the whole schedule of `options` (start, start + step, …, and end
/// when it is not on a step), whatever its slice. \throw InvalidInput as sun_study. Cost O(1).
int sun_study_steps(const SunStudyOptions& options);

/// The study of the whole schedule `whole` (its slice fields ignored) from slices computed
/// apart, given in schedule order and covering it exactly: their steps concatenated, and
/// sun_hours and grid_hours recomputed over all of them exactly as sun_study computes them,
/// so the result equals sun_study(scene, whole) bit for bit.
/// \throw InvalidInput when the slices do not cover the schedule in order or disagree on the
///   faces or the grid. Cost O(steps · (faces + grid points)).
SunStudy combine_sun_studies(const std::vector<SunStudy>& parts, const SunStudyOptions& whole);

}  // namespace hedra
