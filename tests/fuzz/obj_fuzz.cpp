// libFuzzer target: the OBJ reader (io/src/obj.cpp) and the soup-to-bodies checks after it.
#include "fuzz_common.h"
#include "obj.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hedra::fuzz::init();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  hedra::fuzz::mesh_reader("fuzz.obj", hedra::fuzz::bytes_of(data, size), hedra::io::parse_obj);
  return 0;
}
