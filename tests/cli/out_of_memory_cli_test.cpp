// Out of memory (issue 17): a valid input whose result does not fit in the memory this process
// may use ended in "internal error: std::bad_alloc" (exit 1, reserved for bugs). It is a resource
// error: exit 3, one line naming what was being built. The limit comes from `ulimit -v` on the
// child; sanitizer builds do not register this test (AddressSanitizer reserves terabytes of
// address space at start and reports an allocation failure itself instead of throwing).
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include "testing/temp_files.h"

namespace {

namespace fs = std::filesystem;

struct Result {
  int code;
  std::string err;
};

// `hedra ARGS` under a virtual memory limit of `kib` KiB; stderr is what comes back.
Result run_limited(const std::string& args, long kib) {
  const std::string command =
      "ulimit -v " + std::to_string(kib) + " && " + HEDRA_BIN + " " + args + " 2>&1 >/dev/null";
  std::FILE* pipe = ::popen(command.c_str(), "r");
  std::string err;
  std::array<char, 4096> buf;
  while (size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) err.append(buf.data(), n);
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, err};
}

TEST(OutOfMemoryCli, IsAResourceErrorNamingWhatWasBeingBuilt) {
  const fs::path dir = hedra::testing::temp_dir("out_of_memory");
  // 2.2 million side faces (about 2 GB), allowed by the shape's own face budget.
  const std::string scene = hedra::testing::write(dir / "c.json", R"({"version": 1, "bodies": [
    {"name": "c", "cylinder": {"radius": 1, "z": [0, 1], "tolerance": 1e-12, "max_faces": 3000000}}]})");
  const Result r = run_limited("info " + scene, 400'000);
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("out of memory while building the bodies of " + scene), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
}

}  // namespace
