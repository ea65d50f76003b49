// libFuzzer target: the segments file of `hedra clip` (cli/segments.cpp).
#include "cli/segments.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hedra::fuzz::init();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  hedra::fuzz::rejecting_cleanly(
      [&] { hedra::cli::parse_segments("fuzz.txt", hedra::fuzz::bytes_of(data, size)); });
  return 0;
}
