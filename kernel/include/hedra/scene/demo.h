// The embedded demo scene of `hedra demo`, built in code.
#pragma once

#include "hedra/scene/scene.h"

namespace hedra {

/// The demo scene: a ground slab with an L-shaped block, a box and a pyramid standing on it,
/// seen in perspective under the Berlin sun.
Scene demo_scene();

}  // namespace hedra
