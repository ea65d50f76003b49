// `hedra demo`: the embedded demo scene, built in code.
#pragma once

#include "kernel/scene.h"

namespace hedra::cli {

/// The demo scene: a ground slab with an L-shaped block, a box and a pyramid standing on it,
/// seen in perspective under the Berlin sun.
Scene demo_scene();

}  // namespace hedra::cli
