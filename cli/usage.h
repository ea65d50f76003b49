// Usage errors and message hygiene shared by the subcommands.
#pragma once

#include <stdexcept>
#include <string>

namespace CLI {
class App;
class Option;
class Validator;
}

namespace hedra::cli {

/// A bad command line found after parsing (an option value out of range, an option that needs
/// another): printed as one line, exit code 2, like CLI11's own parse errors.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Most worker threads any command accepts (`--threads`); 0 means all available.
constexpr int kMaxThreads = 1024;
/// Largest `render --width` / `--height`, and the most pixels of one image (render/raster.h
/// checks the same product for scene files).
constexpr int kMaxImageSide = 16384;

/// Adds `--threads N` (0 … kMaxThreads) to a subcommand.
CLI::Option* add_threads_option(CLI::App& app, int& threads);

/// The message made safe for one line of a terminal: control characters escaped (\n, \t,
/// \x1b), bytes that are not UTF-8 shown as \xNN, and any run of more than 200 bytes without
/// a space cut with "…". Cost O(length).
std::string sanitize_message(const std::string& message);

/// CLI11 check: a finite number >= 0 (> 0 when `positive`); "nan", "inf" and negative values
/// are usage errors naming the option.
CLI::Validator finite_number(bool positive);

/// A number for messages: %g, so 1e-300 stays 1e-300.
std::string format_number(double value);

}  // namespace hedra::cli
