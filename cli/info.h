// `hedra info`: per-body report (counts, volume, area, convexity, body matrix).
#pragma once

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

/// The bodies of a scene file (visible ones) or of a mesh file (one per component).
/// \throw InvalidInput, IoError.
std::vector<NamedBody> load_bodies(const std::string& path, double coplanar_tolerance = 0,
                                   double planarity_tolerance = -1);

/// A scene file as it is, or a mesh file as a scene of its bodies seen parallel from
/// (1, 2, 1.5) towards the origin, under a directional light from the same side (a mesh file
/// has no camera or lights). What `hlr`, `shadows` and `render` read. \throw InvalidInput, IoError.
Scene load_scene(const std::string& path);

/// Bodies with at most this many faces print their body matrix without --matrix.
constexpr int kSmallBodyFaces = 12;

nlohmann::json info_json(const std::vector<NamedBody>& bodies, bool with_matrix);
void print_info_table(std::ostream& out, const std::vector<NamedBody>& bodies, bool with_matrix);

}  // namespace hedra::cli
