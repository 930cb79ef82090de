// Decodes PNG files for the image-output tests, so that what the renderer
// writes is checked by reading it back with an independent decoder
// (stb_image) rather than by inspecting the encoder's input.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace pt::test {

struct DecodedImage {
  int width = 0, height = 0, channels = 0;
  std::vector<uint8_t> pixels;  ///< row-major, top row first, `channels` bytes per pixel
};

/// Decodes a PNG as stored (no channel conversion); width == 0 when the file
/// does not decode.
DecodedImage decode_png_file(const std::filesystem::path& path);

}  // namespace pt::test
