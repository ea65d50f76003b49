// `hedra info`: per-body report (counts, volume, area, convexity, body matrix).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kernel/body.h"

namespace hedra::cli {

struct NamedBody {
  std::string name;
  Body body;
};

/// Bodies with at most this many faces print their body matrix without --matrix.
constexpr int kSmallBodyFaces = 12;

nlohmann::json info_json(const std::vector<NamedBody>& bodies, bool with_matrix);
void print_info_table(std::ostream& out, const std::vector<NamedBody>& bodies, bool with_matrix);

}  // namespace hedra::cli
