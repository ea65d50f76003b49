// `hedra info`: per-body report (counts, volume, area, convexity, body matrix).
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hedra/core/body.h"
#include "hedra/scene/scene.h"

namespace hedra::cli {

struct NamedBody {
  std::string name;
  Body body;
  std::string lod_note;  // how a curved body's tessellation was chosen, if it was
};

/// The `--tolerance D` of the command (0: exact): meshes read by load_bodies and load_scene
/// have their nearly coplanar neighbouring faces merged and snapped within D (MergeOptions).
void set_import_tolerance(double tolerance);

/// The bodies of a scene file (visible ones) or of a mesh file (one per component). A scene's
/// open surfaces go to `surfaces` when given (what `info` reports), else they are refused
/// (InvalidInput naming the scene file, the body and the first boundary edge: the solid
/// commands). \throw InvalidInput, IoError.
std::vector<NamedBody> load_bodies(const std::string& path,
                                   std::vector<SceneSurface>* surfaces = nullptr);

/// A scene file as it is, or a mesh file as a scene of its bodies seen parallel from
/// (1, 2, 1.5) towards the origin, under a directional light from the same side (a mesh file
/// has no camera or lights). What `hlr`, `shadows` and `render` read. \throw InvalidInput, IoError.
Scene load_scene(const std::string& path);

/// The open-surface report of a mesh file whose surface is not closed (a scan, a terrain, a
/// single face; SceneSurface::of, named after the file), or nullopt when the file is a scene,
/// or its surface has no boundary edge. `info` reports it, and a scene's open surfaces, instead
/// of a body. Cost O(n log n). \throw IoError, InvalidInput (unreadable).
std::optional<SceneSurface> open_surface(const std::string& path);
void print_open_surface(std::ostream& out, const SceneSurface& s, bool json);
/// The report's entry of an open surface ("closed": false, boundary edges, area).
nlohmann::json open_surface_json(const SceneSurface& s);

/// Bodies with at most this many faces print their body matrix without --matrix.
constexpr int kSmallBodyFaces = 12;

nlohmann::json info_json(const std::vector<NamedBody>& bodies, bool with_matrix);
void print_info_table(std::ostream& out, const std::vector<NamedBody>& bodies, bool with_matrix);

}  // namespace hedra::cli
