// The one stb_image implementation of the test suite.
#include "support/png_decode.h"

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

namespace pt::test {

DecodedImage decode_png_file(const std::filesystem::path& path) {
  DecodedImage img;
  unsigned char* data = stbi_load(path.c_str(), &img.width, &img.height, &img.channels, 0);
  if (!data) return DecodedImage{};
  img.pixels.assign(data, data + size_t(img.width) * img.height * img.channels);
  stbi_image_free(data);
  return img;
}

}  // namespace pt::test
