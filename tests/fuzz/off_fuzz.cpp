// libFuzzer target: the OFF reader (io/src/off.cpp) and the soup-to-bodies checks after it.
#include "fuzz_common.h"
#include "off.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hedra::fuzz::init();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  hedra::fuzz::mesh_reader("fuzz.off", hedra::fuzz::bytes_of(data, size), hedra::io::parse_off);
  return 0;
}
