// `hedra demo`: the embedded demo scene, built in code.
#pragma once

#include <vector>

#include "cli/info.h"

namespace hedra::cli {

/// The demo scene: a ground slab with an L-shaped block, a box and a pyramid standing on it.
std::vector<NamedBody> demo_scene();

}  // namespace hedra::cli
