// Wavefront OBJ: "v x y z" and "f i j k …" (1-based, negative = relative, "i/t/n" forms).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "hedra/mesh/merge_coplanar.h"

namespace hedra::io {

/// Parses the geometry of an OBJ file (v and f records; others are ignored). Coordinates as
/// doubles. \throw InvalidInput "file:line: …".
PolygonSoup parse_obj(const std::string& path, const std::string& text);
/// OBJ text, 17 significant digits. `groups` (first polygon, name), in polygon order, start an
/// "o name" record each (names with line breaks or '#' escaped so the record stays one line).
std::string format_obj(const PolygonSoup& soup,
                       const std::vector<std::pair<size_t, std::string>>& groups = {});

}  // namespace hedra::io
