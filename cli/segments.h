// The segments file of `hedra clip`: one segment "x1 y1 z1 x2 y2 z2" per line, '#' comments.
#pragma once

#include <string>
#include <vector>

#include "hedra/core/body.h"

namespace hedra::cli {

struct Segment {
  Vec3 p1, p2;
  int line;  // line number in the file, written as the parts' 7th column
};

/// Parses the text of a segments file; `path` names it in messages. Cost O(length).
/// \throw InvalidInput "file:line: …" for a line without 6 finite numbers or a coordinate
///   beyond ±1e101.
std::vector<Segment> parse_segments(const std::string& path, const std::string& text);

}  // namespace hedra::cli
