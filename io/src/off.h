// OFF (Object File Format): "OFF", counts, vertices, then "k i1 … ik" faces.
#pragma once

#include <string>

#include "hedra/mesh/merge_coplanar.h"

namespace hedra::io {

/// Parses OFF text (also COFF/NOFF/CNOFF headers; colours and normals after the coordinates
/// are ignored). Coordinates are read as doubles. \throw InvalidInput "file:line: …".
PolygonSoup parse_off(const std::string& path, const std::string& text);
/// OFF text with coordinates printed to 17 significant digits (exact round trip).
std::string format_off(const PolygonSoup& soup);

}  // namespace hedra::io
