// libFuzzer target: the scene JSON reader (io/src/scene_json.cpp, io/src/json_value.cpp),
// primitives, transforms, Booleans and level of detail included.
#include "fuzz_common.h"
#include "hedra/io/scene_json.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hedra::fuzz::init();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  hedra::fuzz::rejecting_cleanly(
      [&] { hedra::io::parse_scene("fuzz/scene.json", hedra::fuzz::bytes_of(data, size)); });
  return 0;
}
