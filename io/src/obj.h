// Wavefront OBJ: "v x y z" and "f i j k …" (1-based, negative = relative, "i/t/n" forms).
#pragma once

#include <string>

#include "hedra/mesh/merge_coplanar.h"

namespace hedra::io {

/// Parses the geometry of an OBJ file (v and f records; others are ignored). Coordinates as
/// doubles. \throw InvalidInput "file:line: …".
PolygonSoup parse_obj(const std::string& path, const std::string& text);
/// OBJ text, 17 significant digits.
std::string format_obj(const PolygonSoup& soup);

}  // namespace hedra::io
