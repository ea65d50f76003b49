// The JSON reports of `hedra hlr --json` and `hedra shadows --json`, shared by the command and
// the Python module (python/), so both print the same text for the same result.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

#include "hedra/scene/scene.h"
#include "hedra/visibility/roberts.h"
#include "hedra/visibility/shadows.h"
#include "hedra/visibility/sun_study.h"

namespace hedra::io {

/// {"hidden": […], "junction": […], "ms": T, "visible": […]}: segments [x1,y1,z1,x2,y2,z2] in
/// world coordinates (junction lines only under "junction"), one line, no newline. Doubles
/// print with round-trip precision. Cost O(segments).
std::string hidden_lines_json(const HlrResult& result, double ms);

/// The name of a light type in reports: "directional", "point", "spot" or "sun".
const char* light_type_name(Light::Type type);

/// The report of `hedra shadows --json` (one line, no newline): per light its description and
/// every face's shadow (polygons as rings, hole indices), the k-of-n counts, and, when `study`
/// is given, the "sun_study" object of sun_study_json. `scene_name` fills "scene";
/// `visible_parts` adds the visible shadow polygons (ShadowOptions::visible_parts).
/// \pre result computed for `scene`; study (if any) computed for `scene` with `study_options`.
/// Cost O(output size).
std::string shadows_json(const Scene& scene, const std::string& scene_name,
                         const ShadowResult& result, bool visible_parts, double ms,
                         const SunStudyOptions* study_options = nullptr,
                         const SunStudy* study = nullptr);

/// shadows_json written piece by piece through `write`, in order (the same bytes), holding
/// only a block of faces' text at a time: for a file of hundreds of MB. Cost O(output size).
void write_shadows_json(const std::function<void(std::string_view)>& write, const Scene& scene,
                        const std::string& scene_name, const ShadowResult& result,
                        bool visible_parts, double ms,
                        const SunStudyOptions* study_options = nullptr,
                        const SunStudy* study = nullptr);

namespace internal {
/// write_shadows_json with `block` faces per block and `wave` blocks dumped in parallel between
/// writes (write_shadows_json: 1024 and 64), so that tests can cross many waves on a small
/// scene. The same bytes for any block and wave. \throw std::invalid_argument for 0.
void write_shadows_json_in_waves(const std::function<void(std::string_view)>& write,
                                 const Scene& scene, const std::string& scene_name,
                                 const ShadowResult& result, bool visible_parts, double ms,
                                 size_t block, size_t wave,
                                 const SunStudyOptions* study_options = nullptr,
                                 const SunStudy* study = nullptr);
}  // namespace internal

/// The "sun_study" object of shadows_json alone: place, times, step, per step the sun and the
/// lit fraction of every face, hours of sun per face, the optional grid. Cost O(output size).
std::string sun_study_json(const Scene& scene, const SunStudyOptions& options,
                           const SunStudy& study);

}  // namespace hedra::io
