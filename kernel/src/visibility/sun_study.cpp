#include "hedra/visibility/sun_study.h"

#include <cmath>

#include "hedra/core/error.h"
#include "hedra/core/parallel.h"
#include "visibility/shadows_internal.h"

namespace hedra {

using internal::CasterIndex;
using internal::ShadowBody;
using internal::ShadowFace;
using internal::ShadowSceneAccess;

SunStudy sun_study(const Scene& scene, const SunStudyOptions& options) {
  if (!(options.step_minutes > 0) || !std::isfinite(options.step_minutes))
    throw InvalidInput("sun study: the step must be a positive number of minutes");
  const double span = minutes_between(options.start, options.end);
  if (span < 0)
    throw InvalidInput("sun study: the end " + options.end.to_string() + " is before the start " +
                       options.start.to_string());
  const double count = std::floor(span / options.step_minutes + 1e-9);
  if (count > 10000) throw InvalidInput("sun study: more than 10000 steps");
  sun_position(options.latitude, options.longitude, options.start);  // validates the place

  const ShadowScene prepared(scene);
  const auto& m = ShadowSceneAccess::impl(prepared);
  SunStudy study;
  study.first_face = m.first_face;
  const size_t nf = m.faces.size();
  study.sun_hours.assign(nf, 0);

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
    study.grid_hours.assign(study.grid_points.size(), 0);
  }

  std::vector<double> grid_prev(study.grid_points.size(), 0);
  ShadowOptions so;
  so.polygons = false;
  so.counts = false;
  so.threads = options.threads;
  const long steps = static_cast<long>(count);
  double prev_time = 0;
  for (long k = 0; k <= steps + 1; ++k) {
    double minutes = k * options.step_minutes;
    if (k == steps + 1) {
      if (span - steps * options.step_minutes <= 1e-9) break;  // end already sampled
      minutes = span;
    }
    SunStep step;
    step.time = add_minutes(options.start, minutes);
    const SunPosition sun = sun_position(options.latitude, options.longitude, step.time);
    step.elevation_deg = sun.elevation_deg;
    step.azimuth_deg = sun.azimuth_deg;
    step.sun_up = sun.elevation_deg > 0;
    step.lit_fraction.assign(nf, 0);
    std::vector<double> grid_now(study.grid_points.size(), 0);
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
          const std::vector<OcclusionVolume> volumes = m.volumes(view, options.threads);
          const CasterIndex index(m.pieces, volumes, view, m.scale);
          parallel_for(study.grid_points.size(), options.threads, [&](size_t g) {
            grid_now[g] =
                m.point_hidden(grid_b, grid_f, study.grid_points[g], index, volumes) ? 0 : 1;
          });
        }
      }
    }
    // Trapezoid rule between this step and the previous one.
    if (!study.steps.empty()) {
      const double hours = (minutes - prev_time) / 60;
      const SunStep& last = study.steps.back();
      for (size_t i = 0; i < nf; ++i)
        study.sun_hours[i] += 0.5 * (last.lit_fraction[i] + step.lit_fraction[i]) * hours;
      for (size_t g = 0; g < grid_now.size(); ++g)
        study.grid_hours[g] += 0.5 * (grid_prev[g] + grid_now[g]) * hours;
    }
    prev_time = minutes;
    grid_prev = std::move(grid_now);
    study.steps.push_back(std::move(step));
  }
  return study;
}

}  // namespace hedra
