// `hedra decompose`: convex pieces of the non-convex bodies of a mesh or scene file.
#pragma once

#include <ostream>
#include <string>

namespace hedra::cli {

struct DecomposeCommand {
  std::string file;
  std::string method = "planes";  // planes | float | tetgen | cgal
  double epsilon = 1e-9;          // float method, relative to the body's scale
  bool merge = false;
  std::string out_dir;
  bool json = false;
  int threads = 0;
};

/// Runs the command, printing a table or JSON to `out`. \throw InvalidInput, IoError.
void run_decompose(const DecomposeCommand& command, std::ostream& out);

}  // namespace hedra::cli
