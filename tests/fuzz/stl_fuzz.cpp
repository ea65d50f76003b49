// libFuzzer target: the STL reader, ASCII and binary (the size decides), (io/src/stl.cpp) and the soup-to-bodies checks after it.
#include "fuzz_common.h"
#include "stl.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hedra::fuzz::init();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  hedra::fuzz::mesh_reader("fuzz.stl", hedra::fuzz::bytes_of(data, size), hedra::io::parse_stl);
  return 0;
}
