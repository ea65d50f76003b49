#include "hedra/io/report_json.h"

#include <algorithm>
#include <functional>
#include <stdexcept>
#include <string_view>

#include <nlohmann/json.hpp>

#include "hedra/scene/sun.h"

#include "hedra/core/error.h"
#include "hedra/core/parallel.h"

namespace hedra::io {
namespace {

// nlohmann::json (keys sorted) as `hedra shadows` and `hedra hlr` have always printed them;
// doubles print as the shortest text that reads back to the same double.
using nlohmann::json;

json vec(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

json ring_json(const Polygon3& ring) {
  json r = json::array();
  for (const Vec3& p : ring) r.push_back(vec(p));
  return r;
}

// Rings as a flat list, each outer ring (counter-clockwise seen from outside the body)
// followed by its holes (clockwise).
json polygons_json(const std::vector<ShadowPolygon>& polys) {
  json out = json::array();
  for (const ShadowPolygon& p : polys) {
    out.push_back(ring_json(p.outer));
    for (const Polygon3& h : p.holes) out.push_back(ring_json(h));
  }
  return out;
}

// Which rings of polygons_json(polys) are holes (their indices), so a reader need not tell
// them by orientation.
json hole_indices(const std::vector<ShadowPolygon>& polys) {
  json out = json::array();
  int ring = 0;
  for (const ShadowPolygon& p : polys) {
    ++ring;
    for (size_t h = 0; h < p.holes.size(); ++h) out.push_back(ring++);
  }
  return out;
}

json light_json(const Light& l) {
  json j{{"type", light_type_name(l.type)}, {"intensity", l.intensity}, {"color", vec(l.color)}};
  if (l.type != Light::Type::Point) j["direction"] = vec(l.direction);
  if (l.type == Light::Type::Point || l.type == Light::Type::Spot) j["position"] = vec(l.position);
  if (l.type == Light::Type::Spot) {
    j["cone_deg"] = l.cone_deg;
    j["falloff"] = l.falloff;
  }
  if (l.type == Light::Type::Sun) {
    const SunPosition s = sun_position(l.latitude, l.longitude, l.time);
    j["latitude"] = l.latitude;
    j["longitude"] = l.longitude;
    j["time"] = l.time.to_string();
    j["elevation_deg"] = s.elevation_deg;
    j["azimuth_deg"] = s.azimuth_deg;
  }
  return j;
}

json segments_json(const std::vector<HlrSegment>& list, LineKind kind) {
  json out = json::array();
  for (const HlrSegment& s : list)
    if (s.kind == kind) out.push_back({s.a.x(), s.a.y(), s.a.z(), s.b.x(), s.b.y(), s.b.z()});
  return out;
}

json sun_study_object(const Scene& scene, const SunStudyOptions& options, const SunStudy& study) {
  json st{{"latitude", options.latitude},
          {"longitude", options.longitude},
          {"start", options.start.to_string()},
          {"end", options.end.to_string()},
          {"step_minutes", options.step_minutes}};
  json steps = json::array();
  for (const SunStep& s : study.steps)
    steps.push_back({{"time", s.time.to_string()},
                     {"sun_up", s.sun_up},
                     {"elevation_deg", s.elevation_deg},
                     {"azimuth_deg", s.azimuth_deg},
                     {"lit_fraction", s.lit_fraction}});
  st["steps"] = std::move(steps);
  json faces = json::array();
  for (size_t b = 0; b < scene.bodies().size(); ++b) {
    if (study.first_face[b] < 0) continue;
    for (int f = 0; f < scene.bodies()[b].body.face_count(); ++f)
      faces.push_back(
          {{"body", scene.bodies()[b].name},
           {"face", f},
           {"sun_hours", study.sun_hours[static_cast<size_t>(study.first_face[b] + f)]}});
  }
  st["faces"] = std::move(faces);
  if (!options.grid_body.empty()) {
    json pts = json::array();
    for (const Vec3& p : study.grid_points) pts.push_back(vec(p));
    st["grid"] = {{"body", options.grid_body},
                  {"face", options.grid_face},
                  {"spacing", options.grid_spacing},
                  {"points", std::move(pts)},
                  {"sun_hours", study.grid_hours}};
  }
  return st;
}

}  // namespace

const char* light_type_name(Light::Type t) {
  switch (t) {
    case Light::Type::Directional:
      return "directional";
    case Light::Type::Point:
      return "point";
    case Light::Type::Spot:
      return "spot";
    case Light::Type::Sun:
      return "sun";
  }
  return "directional";
}

std::string hidden_lines_json(const HlrResult& result, double ms) {
  json j;
  j["visible"] = segments_json(result.visible, LineKind::Edge);
  j["hidden"] = segments_json(result.hidden, LineKind::Edge);
  j["junction"] = segments_json(result.visible, LineKind::Junction);
  // Line classes only where the scene has smooth parts: a polyhedral scene's report is as it was.
  if (result.has_smooth()) j["outline"] = segments_json(result.visible, LineKind::Outline);
  if (result.smooth_listed) j["smooth"] = segments_json(result.visible, LineKind::Smooth);
  j["ms"] = ms;
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

// A string that stands for light l's face array until the arrays are spliced in, found as the
// value of a "faces" key (which only this function writes; quotes inside strings are escaped,
// so no name can imitate the key and its value).
std::string face_marker(size_t l) { return "hedra-faces-of-light-" + std::to_string(l) + "-a93f0c"; }

void write_shadows_json(const std::function<void(std::string_view)>& write, const Scene& scene,
                        const std::string& scene_name, const ShadowResult& result,
                        bool visible_parts, double ms, const SunStudyOptions* study_options,
                        const SunStudy* study) {
  internal::write_shadows_json_in_waves(write, scene, scene_name, result, visible_parts, ms,
                                        1024, 64, study_options, study);
}

void internal::write_shadows_json_in_waves(const std::function<void(std::string_view)>& write,
                                           const Scene& scene, const std::string& scene_name,
                                           const ShadowResult& result, bool visible_parts,
                                           double ms, size_t block, size_t wave,
                                           const SunStudyOptions* study_options,
                                           const SunStudy* study) {
  if (block == 0 || wave == 0) throw std::invalid_argument("write_shadows_json: empty block or wave");
  json j;
  j["ms"] = ms;
  j["scene"] = scene_name;
  // The document without the faces: each light's face array is a marker here. The faces'
  // objects are then built and dumped in parallel (a million faces make a document of hundreds
  // of MB: one DOM of it took longer than the shadows), a wave of blocks at a time, and written
  // in order where the marker stands. Objects dump with sorted keys and no spaces, so the bytes
  // are those of dumping the whole document at once; nothing holds more than a wave of them
  // (holding the whole text twice, as faces and as the document, was the peak memory of
  // `hedra shadows` on a million faces).
  json lights = json::array();
  for (size_t l = 0; l < result.lights.size(); ++l)
    lights.push_back({{"light", light_json(result.lights[l].light)}, {"faces", face_marker(l)}});
  j["lights"] = std::move(lights);
  json counts = json::array();
  for (const ShadowCount& c : result.counts)
    counts.push_back({{"body", scene.bodies()[static_cast<size_t>(c.body)].name},
                      {"face", c.face},
                      {"count", c.count},
                      {"of", result.lights.size()},
                      {"umbra", c.count == static_cast<int>(result.lights.size())},
                      {"area", c.area},
                      {"polygons", polygons_json(c.polygons)},
                      {"holes", hole_indices(c.polygons)}});
  j["counts"] = std::move(counts);
  if (study != nullptr && study_options != nullptr)
    j["sun_study"] = sun_study_object(scene, *study_options, *study);
  const std::string text = j.dump(-1, ' ', false, json::error_handler_t::replace);

  // `block` faces per block, `wave` blocks per wave.
  std::vector<std::string> blocks(wave);
  const auto write_faces = [&](const LightShadows& ls) {
    const size_t n = ls.faces.size();
    for (size_t first = 0; first < n; first += block * wave) {
      const size_t count = std::min(n - first, block * wave);
      parallel_chunks(count, block, [&](size_t c, size_t begin, size_t end) {
        std::string& out = blocks[c];
        out.clear();
        for (size_t i = first + begin; i != first + end; ++i) {
          const FaceShadow& fs = ls.faces[i];
          json f{{"body", scene.bodies()[static_cast<size_t>(fs.body)].name},
                 {"face", fs.face},
                 {"area", fs.area},
                 {"self_shadowed", fs.self_shadowed()},
                 {"grazing", fs.grazing()},
                 {"visible", fs.visible},
                 {"shadow_area", fs.shadow_area},
                 {"polygons", polygons_json(fs.polygons)},
                 {"holes", hole_indices(fs.polygons)}};
          if (visible_parts) {
            f["visible_shadow_area"] = fs.visible_shadow_area;
            f["visible_polygons"] = polygons_json(fs.visible_polygons);
          }
          if (i != 0) out += ',';
          out += f.dump(-1, ' ', false, json::error_handler_t::replace);
        }
      });
      for (size_t c = 0; c < (count + block - 1) / block; ++c) write(blocks[c]);
    }
  };
  // The markers, in light order (the document lists the lights in order), become the arrays.
  size_t from = 0;
  for (size_t l = 0; l < result.lights.size(); ++l) {
    // Only a "faces" key can hold the marker (a name equal to it is a "body" value).
    const std::string key = "\"faces\":", quoted = key + "\"" + face_marker(l) + "\"";
    const size_t at = text.find(quoted, from);
    HEDRA_ASSERT(at != std::string::npos, "shadows_json: face marker not found");
    write(std::string_view(text).substr(from, at - from));
    write(key + "[");
    write_faces(result.lights[l]);
    write("]");
    from = at + quoted.size();
  }
  write(std::string_view(text).substr(from));
}

std::string shadows_json(const Scene& scene, const std::string& scene_name,
                         const ShadowResult& result, bool visible_parts, double ms,
                         const SunStudyOptions* study_options, const SunStudy* study) {
  std::string out;
  write_shadows_json([&out](std::string_view s) { out += s; }, scene, scene_name, result,
                     visible_parts, ms, study_options, study);
  return out;
}

std::string sun_study_json(const Scene& scene, const SunStudyOptions& options,
                           const SunStudy& study) {
  return sun_study_object(scene, options, study).dump(-1, ' ', false, json::error_handler_t::replace);
}

}  // namespace hedra::io
