// libFuzzer target: Body::with_exact_solid_bytes, the reader of the exact solid a pickled body
// carries (Python's pickle, the distributed engine). Onto two fixed bodies: a rotated L prism
// (a pending exact image) and a plate drilled after both operands were rotated (a made solid
// with rational corners), whose bytes are the seed corpus. Whatever it accepts must write back
// (exact_solid_bytes) to bytes it reads again and writes identically.
#include <stdexcept>

#include "fuzz_common.h"
#include "hedra/core/primitives.h"
#include "hedra/mesh/boolean.h"

namespace {

const hedra::Body& l_prism() {
  static const hedra::Body b = hedra::prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2)
                                   .transformed(hedra::Transform::rotation({1, 2, 3}, 37));
  return b;
}

const hedra::Body& drilled() {
  static const hedra::Body b = [] {
    const hedra::Transform turn = hedra::Transform::rotation({1, 2, 3}, 37);
    return *hedra::subtract(hedra::box({-2, -2, 0}, {2, 2, 1}).transformed(turn),
                            hedra::cylinder(0.5, -1, 2, 0.1).transformed(turn));
  }();
  return b;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hedra::fuzz::init();
  l_prism();
  drilled();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes = hedra::fuzz::bytes_of(data, size);
  for (const hedra::Body* body : {&l_prism(), &drilled()}) {
    hedra::fuzz::rejecting_cleanly([&] {
      const hedra::Body with = body->with_exact_solid_bytes(bytes);
      const std::string again = with.exact_solid_bytes();
      const std::string third = body->with_exact_solid_bytes(again).exact_solid_bytes();
      if (third != again) throw std::logic_error("exact solid bytes do not write back the same");
    });
  }
  return 0;
}
