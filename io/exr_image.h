// OpenEXR images as linear RGB float texels (through Debian's tinyexr): the
// environment map's input (-e FILE.exr) and a writer for tests and scripts.
// Reading refuses, with one line naming the file, anything an environment
// light cannot use: unreadable or malformed files, empty or absurdly large
// images, and non-finite or negative texels.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "kernels/math/vec3.h"

namespace pt {

/// 12 bytes per texel: linear RGB, row-major, row 0 (the top row) first.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<float3> texels;  ///< width * height entries
};

/// Most texels read_exr accepts (2^28: 3 GiB of float RGB).
inline constexpr uint64_t kMaxExrTexels = uint64_t(1) << 28;

/// The R, G and B channels of a single-part scanline or tiled EXR (half or
/// float; a one-channel image is read as grey). Guarantees width, height >= 1,
/// width * height <= kMaxExrTexels and every component finite and >= 0.
/// Throws InputError "<path>: ..." otherwise (the reasons of
/// read_regular_file, "not an OpenEXR image", "image size W x H ...",
/// "texel (x, y) ... is not finite" / "is negative").
RgbImage read_exr(const std::string& path);

/// The bytes of `image` as an RGB EXR of 32-bit float (or, `half`, 16-bit
/// half) channels, ZIP-compressed unless smaller than 16 x 16; `label` names
/// the image in errors. Throws InputError when the image is empty or its
/// texel count does not match.
std::string encode_exr(const RgbImage& image, bool half, const std::string& label);

/// Writes `image` as a float32 RGB EXR (ZIP-compressed unless smaller than
/// 16 x 16), atomically. Values are written as they are (NaN included, so
/// tests can make hostile files). Throws InputError when the image is empty,
/// its texel count does not match, or the file cannot be written.
void write_exr(const std::string& path, const RgbImage& image);

}  // namespace pt
