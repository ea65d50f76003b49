// PLY (Stanford polygon format): ASCII and binary (little and big endian) reading; ASCII
// writing with double properties.
#pragma once

#include <string>

#include "hedra/mesh/merge_coplanar.h"

namespace hedra::io {

/// Reads the vertex x, y, z properties (any numeric type; double stays double) and the face
/// list property vertex_indices / vertex_index; other elements and properties are skipped.
/// \throw InvalidInput naming the file and the header line or the element.
PolygonSoup parse_ply(const std::string& path, const std::string& bytes);
/// ASCII PLY with double coordinates (exact round trip).
std::string format_ply(const PolygonSoup& soup);

}  // namespace hedra::io
