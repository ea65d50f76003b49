// PNG images (libpng): 8-bit RGB, written atomically.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace hedra::io {

/// Encodes width × height 8-bit RGB pixels (rows top to bottom, 3 bytes per pixel) as PNG.
/// \throw InvalidInput when the sizes do not match the pixel data. Cost O(pixels).
std::string encode_png(int width, int height, const std::vector<uint8_t>& rgb);

/// Writes encode_png's bytes to `path` through a temporary file (hedra/io/atomic_file.h), so a
/// failed run leaves no half-written image. \throw IoError naming the file.
void write_png(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);

/// Reads a PNG file as 8-bit RGB (grey, palette, 16-bit and alpha are converted; alpha is
/// dropped). \throw IoError when the file cannot be read, InvalidInput naming the file when
/// it is not a valid PNG.
std::vector<uint8_t> read_png(const std::string& path, int* width, int* height);

}  // namespace hedra::io
