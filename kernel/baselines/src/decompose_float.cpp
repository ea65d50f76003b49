#include <exception>

#include "decompose/decompose_internal.h"
#include "hedra/baselines/decompose_baselines.h"
#include "hedra/core/error.h"

namespace hedra {

Decomposition decompose_float(const Body& body, double epsilon, const DecomposeOptions& options) {
  if (!(epsilon >= 0)) throw InvalidInput("decompose_float: epsilon must be >= 0");
    try {
    Decomposition d = internal::decompose_with_epsilon(body, epsilon, options);
    for (const Body& piece : d.pieces)
      if (piece.volume() <= 0) throw DecompositionFailed("a piece has no volume");
    return d;
  } catch (const DecompositionCancelled&) {
    throw;
  } catch (const std::exception& e) {
    throw DecompositionFailed(e.what());
  }
}

}  // namespace hedra
