// Shared by the libFuzzer targets: a finding is a crash, a sanitizer report, a hang, memory
// beyond the limit, or any exception other than hedra's typed input errors (InvalidInput,
// IoError), which are the clean way to reject an input (exit 3 in the command).
#pragma once

#include <cstdint>
#include <cstdlib>
#include <string>

#include "hedra/core/error.h"
#include "hedra/mesh/merge_coplanar.h"
#include "hedra/mesh/self_intersection.h"

namespace hedra::fuzz {

/// Inputs are small: a scene's "mesh" that names a device stops at 1 MB, not 1 GiB.
inline void init() { ::setenv("HEDRA_MAX_INPUT_BYTES", "1000000", 1); }

inline std::string bytes_of(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Runs `f`; hedra's input errors are expected outcomes, everything else escapes to libFuzzer.
template <class F>
void rejecting_cleanly(F f) {
  try {
    f();
  } catch (const InvalidInput&) {
  } catch (const IoError&) {
  }
}

/// A mesh reader end to end: parse, then (for soups small enough to keep the run fast) the
/// checks and merging that turn polygons into validated bodies, and the self-intersection
/// check, as io::read_bodies does.
template <class Parse>
void mesh_reader(const std::string& path, const std::string& bytes, Parse parse) {
  rejecting_cleanly([&] {
    const PolygonSoup soup = parse(path, bytes);
    if (soup.polygons.size() <= 256 && soup.vertices.size() <= 1024)
      for (const Body& body : bodies_from_soup(soup)) find_self_intersection(body);
  });
}

}  // namespace hedra::fuzz
