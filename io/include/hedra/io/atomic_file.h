// Output files appear whole or not at all.
#pragma once

#include <string>

namespace hedra::io {

/// Writes `bytes` to a temporary file next to `path`, then renames it over `path`, so a failed
/// run never leaves a half-written file. \throw IoError naming the file.
void write_file_atomically(const std::string& path, const std::string& bytes);

}  // namespace hedra::io
