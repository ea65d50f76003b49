// STL, ASCII and binary. Triangles only; vertices are welded by exact position.
#pragma once

#include <string>

#include "hedra/mesh/merge_coplanar.h"

namespace hedra::io {

/// Parses STL: binary when the size matches 84 + 50·n for the header's n, else ASCII when it
/// starts with "solid", else a binary file whose size is wrong (reported as truncated or a
/// wrong triangle count). ASCII coordinates are read as doubles, binary ones are float32.
/// \throw InvalidInput naming the file and the line or byte offset.
PolygonSoup parse_stl(const std::string& path, const std::string& bytes);
/// Binary STL (float32: coordinates are rounded to single precision).
std::string format_stl_binary(const PolygonSoup& triangles);
/// ASCII STL with 17 significant digits (exact round trip through hedra).
std::string format_stl_ascii(const PolygonSoup& triangles);

}  // namespace hedra::io
