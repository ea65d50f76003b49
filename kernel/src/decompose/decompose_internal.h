// Private entry points of the decomposition engine for hedra::baselines.
#pragma once

#include "hedra/decompose/decompose.h"

namespace hedra::internal {

/// The plane-splitting engine in floating-point mode: on-plane within epsilon · body.scale(),
/// cut points rounded, no symbolic incidence (the engine of decompose_float).
Decomposition decompose_with_epsilon(const Body& body, double epsilon, const DecomposeOptions& options);

}  // namespace hedra::internal
