// Runs the `hedra` binary (HEDRA_BIN) for the end-to-end CLI tests: its exit code, standard
// output and standard error.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace hedra::testing {

struct CliResult {
  int code;
  std::string out;
  std::string err;
};

/// `hedra ARGS`, in directory `cwd` when given; stderr goes through a temporary file.
inline CliResult run_hedra(const std::string& args, const std::filesystem::path& cwd = {}) {
  namespace fs = std::filesystem;
  static int calls = 0;
  const fs::path err_file = fs::temp_directory_path() / ("hedra_cli_stderr_" + std::to_string(::getpid()) + "_" +
                                                         std::to_string(++calls) + ".txt");
  const std::string command = (cwd.empty() ? "" : "cd " + cwd.string() + " && ") + std::string(HEDRA_BIN) + " " +
                              args + " 2>" + err_file.string();
  std::FILE* pipe = ::popen(command.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  std::string err;
  if (std::FILE* f = std::fopen(err_file.c_str(), "r")) {
    while (size_t n = std::fread(buf.data(), 1, buf.size(), f)) err.append(buf.data(), n);
    std::fclose(f);
  }
  fs::remove(err_file);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out, err};
}

}  // namespace hedra::testing
