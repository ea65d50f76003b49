#include "cli/shadows.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "cli/distributed_study.h"
#include "cli/info.h"
#include "cli/progress.h"
#include "cli/usage.h"
#include "hedra/io/atomic_file.h"
#include "hedra/io/report_json.h"
#include "hedra/core/error.h"
#include "hedra/visibility/roberts.h"
#include "hedra/visibility/shadows.h"
#include "hedra/scene/sun.h"
#include "hedra/clip/polygon_clip.h"
#include "hedra/render/raster.h"
#include "hedra/render/svg.h"

namespace hedra::cli {
namespace {

std::string light_label(const Light& l) {
  char buf[200];
  switch (l.type) {
    case Light::Type::Sun: {
      const SunPosition s = sun_position(l.latitude, l.longitude, l.time);
      std::snprintf(buf, sizeof buf, "sun at %.4g, %.4g, %s (elevation %.2f°, azimuth %.2f°)",
                    l.latitude, l.longitude, l.time.to_string().c_str(), s.elevation_deg,
                    s.azimuth_deg);
      break;
    }
    case Light::Type::Directional:
      std::snprintf(buf, sizeof buf, "directional (%.4g, %.4g, %.4g)", l.direction.x(),
                    l.direction.y(), l.direction.z());
      break;
    case Light::Type::Point:
    case Light::Type::Spot:
      std::snprintf(buf, sizeof buf, "%s at (%.4g, %.4g, %.4g)", io::light_type_name(l.type),
                    l.position.x(),
                    l.position.y(), l.position.z());
      break;
  }
  return buf;
}

// "hh:mm" on the given date, or a full ISO 8601 time.
std::optional<UtcTime> parse_time(const std::string& text, const UtcTime* date) {
  if (text.size() == 5 && text[2] == ':' && date != nullptr) {
    char iso[32];
    std::snprintf(iso, sizeof iso, "%04d-%02d-%02dT%s:00Z", date->year, date->month, date->day,
                  text.c_str());
    try {
      return UtcTime::parse(iso);
    } catch (const InvalidInput&) {
      return std::nullopt;
    }
  }
  try {
    return UtcTime::parse(text);
  } catch (const InvalidInput&) {
    return std::nullopt;
  }
}

// Step in minutes: "30", "30m", "30min" or "0.5h".
std::optional<double> parse_step(const std::string& text) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  const std::string unit = text.substr(used);
  if (unit == "h")
    v *= 60;
  else if (!(unit.empty() || unit == "m" || unit == "min"))
    return std::nullopt;
  if (!(v > 0) || !std::isfinite(v)) return std::nullopt;
  return v;
}

const Light* scene_sun(const Scene& scene) {
  for (const Light& l : scene.lights)
    if (l.type == Light::Type::Sun) return &l;
  return nullptr;
}

// The top face of the body named "ground": the face whose outward normal is +z, highest.
int ground_top(const Scene& scene, int& body) {
  body = -1;
  for (size_t b = 0; b < scene.bodies().size(); ++b)
    if (scene.bodies()[b].name == "ground" && !scene.bodies()[b].hidden) body = static_cast<int>(b);
  if (body < 0) return -1;
  const Body& g = scene.bodies()[static_cast<size_t>(body)].body;
  int best = -1;
  double z = -1e300;
  for (int f = 0; f < g.face_count(); ++f) {
    if (g.inner_normal(f).z() > -0.999999) continue;
    const double fz =
        g.vertices()[static_cast<size_t>(g.faces()[static_cast<size_t>(f)].loops[0][0])].z();
    if (fz > z) {
      z = fz;
      best = f;
    }
  }
  return best;
}

// The hidden-line drawing with the visible parts of the shadow polygons under its lines:
// one filled path per light and face (even–odd, so holes stay open), semi-transparent, so the
// umbra of several lights comes out darker. Framed as `hedra render` frames the scene, or (fit)
// fitted to the image; in perspective every ring is first clipped by the near plane the
// drawing's lines are clipped by (ring by ring: even–odd of the clipped rings is the clipped
// polygon).
std::string shadows_svg(const Scene& scene, const ShadowResult& result, const std::string& title,
                        bool fit) {
  const HlrResult lines = hidden_lines(scene, HlrOptions{});
  SvgStyle style;
  style.width = scene.camera.width;
  style.height = scene.camera.height;
  style.background = scene.image.background;
  style.title = title;
  if (!fit) style.view = scene_view(scene, style.width, style.height);
  std::string svg = hidden_lines_svg(lines, style);
  const SvgFrame frame(style, lines);
  const PictureProjection projection(scene.camera);
  const auto to_pixels = [&](const Vec3& p) -> Vec2 {
    return frame.pixels(p, style.view ? Vec2::Zero() : projection.project(p));
  };
  std::optional<ExactPlane> near;
  if (scene.camera.projection == Camera::Projection::Perspective)
    near = ExactPlane::from_coefficients(scene.camera.near_plane(scene.bbox()));
  static const char* colours[] = {"#1f3b73", "#73251f", "#1f7335", "#6b1f73"};
  std::string group = "<g id=\"shadows\" stroke=\"none\" fill-rule=\"evenodd\">\n";
  char buf[64];
  for (size_t l = 0; l < result.lights.size(); ++l) {
    for (const FaceShadow& fs : result.lights[l].faces) {
      if (fs.visible_polygons.empty()) continue;
      std::string d;
      auto ring = [&](const Polygon3& r) {
        for (size_t i = 0; i < r.size(); ++i) {
          const Vec2 p = to_pixels(r[i]);
          std::snprintf(buf, sizeof buf, "%s%.2f %.2f", i ? " L" : "M", p.x(), p.y());
          d += buf;
        }
        d += " Z ";
      };
      const auto clipped_ring = [&](const Polygon3& r) {
        if (!near) return ring(r);
        for (const Polygon3& piece : clip_polygon(r, *near)) ring(piece);
      };
      for (const ShadowPolygon& p : fs.visible_polygons) {
        clipped_ring(p.outer);
        for (const Polygon3& h : p.holes) clipped_ring(h);
      }
      // Inline style: the drawing's stylesheet sets `path { fill: none }`.
      group += "<path style=\"fill:" + std::string(colours[l % 4]) +
               ";fill-opacity:0.35;fill-rule:evenodd;stroke:none\" d=\"" + d + "\"/>\n";
    }
  }
  group += "</g>\n";
  // Under the lines: before the first group of the drawing.
  const size_t at = svg.find("<g");
  svg.insert(at == std::string::npos ? svg.rfind("</svg>") : at, group);
  return svg;
}

// The grid's spacing: a finite positive number that puts at most kMaxGridPoints samples on the
// face (its bounding box over spacing², so 1e-300 does not ask for 1e600 points).
constexpr double kMaxGridPoints = 1e6;
void check_grid(const Scene& scene, const SunStudyOptions& o) {
  if (!(o.grid_spacing > 0) || !std::isfinite(o.grid_spacing))
    throw UsageError("--grid: the spacing must be a finite positive number, got " +
                     format_number(o.grid_spacing));
  if (!scene.contains(o.grid_body)) return;  // the study names a missing body itself
  const Body& body = scene.get(o.grid_body).body;
  if (o.grid_face < 0 || o.grid_face >= body.face_count()) return;
  Eigen::AlignedBox3d box;
  box.setEmpty();
  for (const auto& loop : body.faces()[static_cast<size_t>(o.grid_face)].loops)
    for (int v : loop) box.extend(body.vertices()[static_cast<size_t>(v)]);
  const Vec3 size = box.sizes();
  const double points = (size.maxCoeff() / o.grid_spacing + 1) * (size.maxCoeff() / o.grid_spacing + 1);
  if (points > kMaxGridPoints)
    throw UsageError("--grid: spacing " + format_number(o.grid_spacing) + " puts about " +
                     format_number(points) + " sample points on face " +
                     std::to_string(o.grid_face) + " of '" + o.grid_body + "' (at most " +
                     format_number(kMaxGridPoints) + ")");
}

}  // namespace

CLI::App* add_shadows_subcommand(CLI::App& app, ShadowsCommand& command) {
  CLI::App* sub = app.add_subcommand(
      "shadows", "Self shadows, exact cast-shadow polygons and sun hours of a scene's faces");
  sub->add_option("scene", command.scene_file, "scene or mesh file")->required();
  sub->add_option("--json", command.json_file, "write the report: faces, polygons, counts (JSON)");
  sub->add_option("--svg", command.svg_file,
                  "write the shadows over the hidden-line drawing (SVG)");
  sub->add_flag("--fit", command.fit,
                "with --svg: fit the drawing to the image (default: frame it as `hedra render` "
                "does)");
  sub->add_option("--sun-hours", command.sun_hours,
                  "sun study START END STEP: UTC times (ISO 8601, or hh:mm on the date of the "
                  "scene's sun) and the step in minutes (30, 30m, 0.5h)")
      ->expected(3)
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            if (parse_step(v) || parse_time(v, nullptr) || (v.size() == 5 && v[2] == ':'))
              return "";
            return "'" + v +
                   "' is neither a time (2026-06-21T04:00:00Z or hh:mm) nor a step in minutes";
          },
          "TIME|STEP"));
  sub->add_option("--grid", command.grid,
                  "with --sun-hours: hours of sun at sample points on one face: BODY FACE SPACING")
      ->expected(3);
  sub->add_flag("--visible", command.visible_parts,
                "report the parts of the shadows the camera sees (always with --svg)");
  add_threads_option(*sub, command.threads);
  auto* workers = sub->add_option("--workers", command.workers,
                                  "with --sun-hours: run the study on a local Dask cluster of N "
                                  "processes (docs/distributed.md)")
                      ->check(CLI::PositiveNumber);
  sub->add_option("--scheduler", command.scheduler,
                  "with --sun-hours: run the study on the Dask cluster of this scheduler "
                  "(tcp://host:8786)")
      ->excludes(workers);
  return sub;
}

void run_shadows(const ShadowsCommand& command, std::ostream& out) {
  const Scene scene = load_scene(command.scene_file);
  if (scene.lights.empty())
    throw InvalidInput(command.scene_file +
                       ": the scene has no lights (shadows need at least one)");

  // The sun study's inputs, checked before any work.
  std::optional<SunStudyOptions> study_options;
  if (!command.sun_hours.empty()) {
    const Light* sun = scene_sun(scene);
    if (sun == nullptr)
      throw InvalidInput(
          command.scene_file +
          ": --sun-hours needs a sun light in the scene (its latitude and longitude)");
    SunStudyOptions o;
    o.latitude = sun->latitude;
    o.longitude = sun->longitude;
    const auto start = parse_time(command.sun_hours[0], &sun->time);
    const auto end = parse_time(command.sun_hours[1], &sun->time);
    const auto step = parse_step(command.sun_hours[2]);
    if (!start || !end || !step)
      throw InvalidInput("--sun-hours: expected START END STEP (times, then minutes), got '" +
                         command.sun_hours[0] + " " + command.sun_hours[1] + " " +
                         command.sun_hours[2] + "'");
    o.start = *start;
    o.end = *end;
    o.step_minutes = *step;
    o.threads = command.threads;
    if (!command.grid.empty()) {
      o.grid_body = command.grid[0];
      try {
        o.grid_face = std::stoi(command.grid[1]);
        o.grid_spacing = std::stod(command.grid[2]);
      } catch (const std::exception&) {
        throw UsageError("--grid: expected BODY FACE SPACING, got '" + command.grid[1] + " " +
                         command.grid[2] + "'");
      }
      check_grid(scene, o);
    }
    study_options = o;
  } else if (!command.grid.empty()) {
    throw UsageError("--grid needs --sun-hours");
  }
  const bool on_dask = command.workers > 0 || !command.scheduler.empty();
  if (on_dask && !study_options)
    throw InvalidInput(std::string(command.workers > 0 ? "--workers" : "--scheduler") +
                       " needs --sun-hours");

  // The computation, timed without file I/O.
  ShadowOptions options;
  options.threads = command.threads;
  options.visible_parts = command.visible_parts || !command.svg_file.empty();
  options.progress = progress_bar("shadows");
  const auto t0 = std::chrono::steady_clock::now();
  ShadowResult result;
  std::optional<SunStudy> study;
  std::optional<nlohmann::json> dask_study;  // the `sun_study` JSON of a study run on a Dask cluster
  try {
    result = compute_shadows(scene, options);
    if (study_options && on_dask)
      dask_study = distributed_sun_study(command.scene_file, *study_options,
                                         {command.workers, command.scheduler});
    else if (study_options)
      study = sun_study(scene, *study_options);
  } catch (const InvalidInput& e) {
    end_progress_bar();
    throw InvalidInput(command.scene_file + ": " + e.what());
  }
  end_progress_bar();
  check_interrupted();  // the sun study has no reports: a Ctrl-C during it stops here
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  // Everything is formatted before anything is visible: the outputs are staged under
  // temporary names and renamed together.
  std::string svg_text;
  if (!command.svg_file.empty()) {
    try {
      svg_text = shadows_svg(scene, result, "hedra shadows " + command.scene_file, command.fit);
    } catch (const InvalidInput& e) {
      throw InvalidInput(command.scene_file + ": " + e.what());
    }
  }
  io::OutputTransaction outputs;  // both files or neither
  if (!command.json_file.empty()) {
    const SunStudyOptions* so = study ? &*study_options : nullptr;
    const SunStudy* st = study ? &*study : nullptr;
    if (dask_study) {
      // The report as always, with the cluster's sun_study object: the same bytes as one
      // process's (nlohmann prints a parsed double as it was printed).
      nlohmann::json j = nlohmann::json::parse(
          io::shadows_json(scene, command.scene_file, result, options.visible_parts, ms, so, st));
      j["sun_study"] = *dask_study;
      outputs.add(command.json_file, j.dump() + "\n");
    } else {
      // Written as it is formatted: a million faces make hundreds of MB of text.
      outputs.add(command.json_file, [&](const std::function<void(std::string_view)>& write) {
        io::write_shadows_json(write, scene, command.scene_file, result, options.visible_parts, ms, so, st);
        write("\n");
      });
    }
  }
  if (!command.svg_file.empty()) outputs.add(command.svg_file, svg_text);
  check_interrupted();  // Ctrl-C up to here: no file
  outputs.commit();

  // Summary.
  char buf[256];
  int faces = 0;
  for (const SceneBody* b : scene.visible_bodies()) faces += b->body.face_count();
  std::snprintf(buf, sizeof buf, "shadows: %zu bodies, %d faces, %zu light%s; %.3g ms\n",
                scene.visible_bodies().size(), faces, result.lights.size(),
                result.lights.size() == 1 ? "" : "s", ms);
  out << buf;
  for (size_t l = 0; l < result.lights.size(); ++l) {
    int self = 0, grazing = 0, cast = 0;
    double cast_area = 0;
    for (const FaceShadow& fs : result.lights[l].faces) {
      self += fs.self_shadowed();
      grazing += fs.grazing();
      if (!fs.self_shadowed() && fs.shadow_area > 0) {
        ++cast;
        cast_area += fs.shadow_area;
      }
    }
    std::snprintf(buf, sizeof buf,
                  "  light %zu, %s: %d self-shadowed faces, %d grazing, cast shadows on %d faces "
                  "(area %.6g)\n",
                  l + 1, light_label(result.lights[l].light).c_str(), self, grazing, cast,
                  cast_area);
    out << buf;
  }
  if (result.lights.size() >= 2) {
    double umbra = 0, partial = 0;
    for (const ShadowCount& c : result.counts)
      (c.count == static_cast<int>(result.lights.size()) ? umbra : partial) += c.area;
    std::snprintf(buf, sizeof buf, "  umbra (all %zu lights) %.6g, partial shadow %.6g\n",
                  result.lights.size(), umbra, partial);
    out << buf;
  }
  if (study) {
    int up = 0;
    for (const SunStep& s : study->steps) up += s.sun_up;
    double lo = 1e300, hi = 0;
    for (double h : study->sun_hours) {
      lo = std::min(lo, h);
      hi = std::max(hi, h);
    }
    std::snprintf(buf, sizeof buf,
                  "  sun study: %zu steps from %s to %s, sun up at %d; hours of direct sun per "
                  "face from %.3g to %.3g\n",
                  study->steps.size(), study_options->start.to_string().c_str(),
                  study_options->end.to_string().c_str(), up, lo, hi);
    out << buf;
  }
  if (dask_study) out << sun_study_summary(*dask_study);
  if (!command.json_file.empty() || !command.svg_file.empty()) {
    out << "wrote";
    if (!command.json_file.empty()) out << " " << command.json_file;
    if (!command.svg_file.empty()) out << " " << command.svg_file;
    out << "\n";
  }
}

void write_demo_shadows(const Scene& scene, const std::string& path, std::ostream& out) {
  ShadowOptions options;
  options.visible_parts = true;
  const ShadowResult result = compute_shadows(scene, options);
  io::write_file_atomically(path, shadows_svg(scene, result, "hedra demo: shadows", false));
  int body = -1;
  const int face = ground_top(scene, body);
  out << "shadows (exact polygons): ";
  if (face >= 0 && !result.lights.empty()) {
    const FaceShadow& g = result.face(0, body, face);
    char buf[160];
    std::snprintf(buf, sizeof buf, "shadowed area of the ground %.6g of %.6g (%.2f %%), ",
                  g.shadow_area, g.area, 100 * g.shadow_area / g.area);
    out << buf;
  }
  out << "wrote " << path << "\n";
}

}  // namespace hedra::cli
