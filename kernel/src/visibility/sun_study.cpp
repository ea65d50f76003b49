#include "hedra/visibility/sun_study.h"

#include <cmath>

#include "hedra/core/error.h"
#include "hedra/core/parallel.h"
#include "visibility/shadows_internal.h"

namespace hedra {
namespace {

using internal::ShadowBody;
using internal::CasterIndex;
using internal::PieceVolumes;
using internal::ShadowFace;
using internal::ShadowSceneAccess;

// The schedule: step k at k · step minutes after the start for k = 0 … whole, and one more
// step at the end when it is not on a step (more than 1e-9 minutes after the last).
struct Schedule {
  double span = 0;  // minutes from start to end
  long whole = 0;   // whole steps within the span
  int steps = 0;    // steps in all
};

Schedule schedule_of(const SunStudyOptions& options) {
  if (!(options.step_minutes > 0) || !std::isfinite(options.step_minutes))
    throw InvalidInput("sun study: the step must be a positive number of minutes");
  Schedule s;
  s.span = minutes_between(options.start, options.end);
  if (s.span < 0)
    throw InvalidInput("sun study: the end " + options.end.to_string() + " is before the start " +
                       options.start.to_string());
  const double count = std::floor(s.span / options.step_minutes + 1e-9);
  if (count > 10000) throw InvalidInput("sun study: more than 10000 steps");
  s.whole = static_cast<long>(count);
  const bool extra = !(s.span - s.whole * options.step_minutes <= 1e-9);  // end not sampled
  s.steps = static_cast<int>(s.whole + 1 + (extra ? 1 : 0));
  return s;
}

// Minutes after the start of step k of the schedule.
double minutes_of(const Schedule& s, const SunStudyOptions& options, long k) {
  return k == s.whole + 1 ? s.span : k * options.step_minutes;
}

// sun_hours and grid_hours over the steps, step k of the study being step first + k of the
// schedule: the trapezoid rule between consecutive steps, accumulated in step order (the one
// place that sums them, so slices joined later give the same bits).
void integrate(SunStudy& study, size_t nf, const Schedule& s, const SunStudyOptions& options) {
  study.sun_hours.assign(nf, 0);
  study.grid_hours.assign(study.grid_points.size(), 0);
  for (size_t k = 1; k < study.steps.size(); ++k) {
    const long at = study.first_step + static_cast<long>(k);
    const double hours = (minutes_of(s, options, at) - minutes_of(s, options, at - 1)) / 60;
    const SunStep &last = study.steps[k - 1], &step = study.steps[k];
    for (size_t i = 0; i < nf; ++i)
      study.sun_hours[i] += 0.5 * (last.lit_fraction[i] + step.lit_fraction[i]) * hours;
    for (size_t g = 0; g < step.grid_lit.size(); ++g)
      study.grid_hours[g] +=
          0.5 * (static_cast<double>(last.grid_lit[g]) + static_cast<double>(step.grid_lit[g])) *
          hours;
  }
}

}  // namespace

int sun_study_steps(const SunStudyOptions& options) { return schedule_of(options).steps; }

SunStudy sun_study(const Scene& scene, const SunStudyOptions& options) {
  const Schedule schedule = schedule_of(options);
  sun_position(options.latitude, options.longitude, options.start);  // validates the place
  const int first = options.first_step;
  const int count = options.step_count < 0 ? schedule.steps - first : options.step_count;
  if (first < 0 || first > schedule.steps || count < 0 || count > schedule.steps - first)
    throw InvalidInput("sun study: steps " + std::to_string(first) + " to " +
                       std::to_string(first + count - 1) + " lie outside the schedule's " +
                       std::to_string(schedule.steps) + " steps");

  const ShadowScene prepared(scene);
  const auto& m = ShadowSceneAccess::impl(prepared);
  SunStudy study;
  study.first_step = first;
  study.first_face = m.first_face;
  const size_t nf = m.faces.size();

  // The grid on the chosen face.
  int grid_b = -1, grid_f = options.grid_face;
  if (!options.grid_body.empty()) {
    for (size_t b = 0; b < m.bodies.size(); ++b)
      if (m.bodies[b].name == options.grid_body) grid_b = static_cast<int>(b);
    if (grid_b < 0)
      throw InvalidInput("sun study: no visible body named '" + options.grid_body + "'");
    const Body& body = m.bodies[static_cast<size_t>(grid_b)].body;
    if (grid_f < 0 || grid_f >= body.face_count())
      throw InvalidInput("sun study: body '" + options.grid_body + "' has no face " +
                         std::to_string(grid_f));
    if (!(options.grid_spacing > 0))
      throw InvalidInput("sun study: the grid spacing must be positive");
    const ShadowFace& fd = m.bodies[static_cast<size_t>(grid_b)].faces[static_cast<size_t>(grid_f)];
    // Sample the face's 2D box at cell centres; keep points strictly inside a convex part.
    Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
    const std::vector<Ring2> parts2d = fd.parts2d();
    for (const Ring2& r : parts2d)
      for (const Vec2& q : r) {
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
    const double s = options.grid_spacing / std::sqrt(fd.area_factor);  // spacing along the face
    const long nx = static_cast<long>(std::ceil((hi.x() - lo.x()) / s)),
               ny = static_cast<long>(std::ceil((hi.y() - lo.y()) / s));
    if (nx * ny > 1000000) throw InvalidInput("sun study: the grid has more than a million points");
    for (long y = 0; y < ny; ++y)
      for (long x = 0; x < nx; ++x) {
        const Vec2 q(lo.x() + (x + 0.5) * s, lo.y() + (y + 0.5) * s);
        bool inside = false;
        for (const Ring2& r : parts2d) {
          bool in = true;
          for (size_t i = 0; i < r.size() && in; ++i)
            in = orient2d(r[i], r[(i + 1) % r.size()], q) == Sign::Positive;
          inside = inside || in;
        }
        if (inside) study.grid_points.push_back(fd.lift(q));
      }
  }

  ShadowOptions so;
  so.polygons = false;
  so.counts = false;
  so.threads = options.threads;
  for (long k = first; k < first + count; ++k) {
    SunStep step;
    step.time = add_minutes(options.start, minutes_of(schedule, options, k));
    const SunPosition sun = sun_position(options.latitude, options.longitude, step.time);
    step.elevation_deg = sun.elevation_deg;
    step.azimuth_deg = sun.azimuth_deg;
    step.sun_up = sun.elevation_deg > 0;
    step.lit_fraction.assign(nf, 0);
    step.grid_lit.assign(study.grid_points.size(), 0);
    if (step.sun_up) {
      Light light;
      light.type = Light::Type::Sun;
      light.latitude = options.latitude;
      light.longitude = options.longitude;
      light.time = step.time;
      light.direction = -sun.towards_sun;
      const ShadowResult r = prepared.compute({light}, so);
      for (size_t i = 0; i < nf; ++i) {
        const FaceShadow& fs = r.lights[0].faces[i];
        step.lit_fraction[i] = fs.to_light == Facing::Front ? fs.lit_fraction() : 0;
      }
      if (!study.grid_points.empty()) {
        const Viewpoint view = Viewpoint::of(light);
        const ShadowBody& bd = m.bodies[static_cast<size_t>(grid_b)];
        if (facing(bd.faces[static_cast<size_t>(grid_f)].plane, view) == Facing::Front) {
          const PieceVolumes volumes = m.volumes(view, options.threads);
          const CasterIndex index(m.pieces, volumes, view, m.scale, options.threads);
          parallel_for(study.grid_points.size(), options.threads, [&](size_t g) {
            step.grid_lit[g] =
                m.point_hidden(grid_b, grid_f, study.grid_points[g], index, volumes) ? 0 : 1;
          });
        }
      }
    }
    study.steps.push_back(std::move(step));
  }
  integrate(study, nf, schedule, options);
  return study;
}

SunStudy combine_sun_studies(const std::vector<SunStudy>& parts, const SunStudyOptions& whole) {
  const Schedule schedule = schedule_of(whole);
  SunStudy out;
  int next = 0;
  for (size_t p = 0; p < parts.size(); ++p) {
    const SunStudy& part = parts[p];
    if (part.first_step != next)
      throw InvalidInput("sun study: slice " + std::to_string(p) + " starts at step " +
                         std::to_string(part.first_step) + ", expected step " +
                         std::to_string(next));
    if (p == 0) {
      out.first_face = part.first_face;
      out.grid_points = part.grid_points;
    } else if (part.first_face != out.first_face || part.grid_points != out.grid_points) {
      throw InvalidInput("sun study: slice " + std::to_string(p) +
                         " has other faces or another grid than slice 0");
    }
    out.steps.insert(out.steps.end(), part.steps.begin(), part.steps.end());
    next += static_cast<int>(part.steps.size());
  }
  if (next != schedule.steps)
    throw InvalidInput("sun study: the slices cover " + std::to_string(next) + " of the " +
                       std::to_string(schedule.steps) + " steps");
  integrate(out, out.steps.front().lit_fraction.size(), schedule, whole);
  return out;
}

}  // namespace hedra
