#include "hedra/core/error.h"

#include <cstdlib>
#include <cstring>

namespace hedra::detail {

void assertion_failed(const char* what) { throw InternalError(what); }

bool expensive_checks() {
  static const bool on = [] {
    const char* v = std::getenv("HEDRA_EXPENSIVE_CHECKS");
    return v != nullptr && *v != '\0' && std::strcmp(v, "0") != 0;
  }();
  return on;
}

}  // namespace hedra::detail
