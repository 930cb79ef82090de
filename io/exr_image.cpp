// read_exr and write_exr over tinyexr's in-memory API: the file itself is
// read (and written) by io/, so directories, FIFOs and oversized files are
// refused as for every other input, and output is atomic.
#include "exr_image.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string_view>

#include <tinyexr.h>

#include "atomic_file.h"
#include "read_file.h"
#include "scene_error.h"

namespace pt {
namespace {

/// Compressed EXRs are smaller than their texels; uncompressed float RGBA of
/// kMaxExrTexels plus headers and offset tables stays below this.
constexpr uint64_t kMaxExrFileBytes = uint64_t(1) << 33;

struct FreeDeleter {
  void operator()(void* p) const { std::free(p); }
};

/// tinyexr's message (freed here) as " (tinyexr: ...)", or "" when it gave none.
std::string take_message(const char* err) {
  if (err == nullptr) return "";
  std::string_view message(err);
  while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back()))) message.remove_suffix(1);
  std::string text = " (tinyexr: " + excerpt(message, 80) + ")";
  FreeEXRErrorMessage(err);
  return text;
}

/// The header checks made before any texel is decoded (so that a forged
/// size cannot make tinyexr allocate): one part, float or half channels,
/// and a size within kMaxExrTexels.
void check_header(const std::string& path, const unsigned char* data, size_t size) {
  auto fail = [&](const std::string& what) { return InputError(path + ": " + what); };
  EXRVersion version;
  if (ParseEXRVersionFromMemory(&version, data, size) != TINYEXR_SUCCESS)
    throw fail("not an OpenEXR image (no EXR magic number and version)");
  if (version.multipart || version.non_image) throw fail("multi-part and deep EXR images are not supported");
  EXRHeader header;
  InitEXRHeader(&header);
  const char* err = nullptr;
  if (ParseEXRHeaderFromMemory(&header, &version, data, size, &err) != TINYEXR_SUCCESS)
    throw fail("not an OpenEXR image: bad header" + take_message(err));
  const int64_t w = int64_t(header.data_window.max_x) - header.data_window.min_x + 1;
  const int64_t h = int64_t(header.data_window.max_y) - header.data_window.min_y + 1;
  bool uint_channel = false;
  for (int c = 0; c < header.num_channels; ++c) uint_channel |= header.pixel_types[c] == TINYEXR_PIXELTYPE_UINT;
  FreeEXRHeader(&header);
  const std::string dims = "image size " + std::to_string(w) + " x " + std::to_string(h);
  if (w <= 0 || h <= 0) throw fail(dims + " is empty");
  if (uint64_t(w) * uint64_t(h) > kMaxExrTexels)
    throw fail(dims + " exceeds " + std::to_string(kMaxExrTexels) + " texels");
  if (uint_channel) throw fail("has an integer (UINT) channel; an environment map needs half or float RGB");
}

/// Throws for the first texel with a non-finite or negative component.
void check_texels(const std::string& path, const RgbImage& img) {
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const float3& t = img.texels[size_t(y) * img.width + x];
      if (is_finite(t) && t.x >= 0 && t.y >= 0 && t.z >= 0) continue;
      const std::string where = path + ": texel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
      throw InputError(where + (is_finite(t) ? " is negative" : " is not finite"));
    }
}

}  // namespace

RgbImage read_exr(const std::string& path) {
  const std::string bytes = read_regular_file(path, "file in OpenEXR format", kMaxExrFileBytes);
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  check_header(path, data, bytes.size());

  float* rgba = nullptr;
  RgbImage img;
  const char* err = nullptr;
  if (LoadEXRFromMemory(&rgba, &img.width, &img.height, data, bytes.size(), &err) != TINYEXR_SUCCESS)
    throw InputError(path + ": not a readable RGB EXR image" + take_message(err));
  std::unique_ptr<float, FreeDeleter> owned(rgba);
  if (img.width <= 0 || img.height <= 0 || uint64_t(img.width) * uint64_t(img.height) > kMaxExrTexels)
    throw InputError(path + ": decoded image size is out of range");

  img.texels.resize(size_t(img.width) * img.height);
  for (size_t i = 0; i < img.texels.size(); ++i) img.texels[i] = {rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]};
  check_texels(path, img);
  return img;
}

std::string encode_exr(const RgbImage& image, bool half, const std::string& label) {
  if (image.width <= 0 || image.height <= 0 || image.texels.size() != size_t(image.width) * image.height)
    throw InputError(label + ": cannot write an EXR of " + std::to_string(image.width) + " x " +
                     std::to_string(image.height) + " with " + std::to_string(image.texels.size()) + " texels");
  // Channel planes in the (alphabetical) order EXR readers expect: B, G, R.
  const size_t n = image.texels.size();
  std::vector<float> planes(3 * n);
  for (size_t i = 0; i < n; ++i) {
    planes[i] = image.texels[i].z;
    planes[n + i] = image.texels[i].y;
    planes[2 * n + i] = image.texels[i].x;
  }
  float* plane_ptrs[3] = {planes.data(), planes.data() + n, planes.data() + 2 * n};

  EXRChannelInfo channels[3] = {};
  std::strcpy(channels[0].name, "B");
  std::strcpy(channels[1].name, "G");
  std::strcpy(channels[2].name, "R");
  int pixel_types[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
  const int stored = half ? TINYEXR_PIXELTYPE_HALF : TINYEXR_PIXELTYPE_FLOAT;
  int requested[3] = {stored, stored, stored};

  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = 3;
  header.channels = channels;
  header.pixel_types = pixel_types;
  header.requested_pixel_types = requested;
  header.compression_type =
      (image.width < 16 && image.height < 16) ? TINYEXR_COMPRESSIONTYPE_NONE : TINYEXR_COMPRESSIONTYPE_ZIP;
  EXRImage exr;
  InitEXRImage(&exr);
  exr.num_channels = 3;
  exr.images = reinterpret_cast<unsigned char**>(plane_ptrs);
  exr.width = image.width;
  exr.height = image.height;

  unsigned char* memory = nullptr;
  const char* err = nullptr;
  const size_t size = SaveEXRImageToMemory(&exr, &header, &memory, &err);
  std::unique_ptr<unsigned char, FreeDeleter> owned(memory);
  if (size == 0 || memory == nullptr) throw InputError(label + ": cannot encode the EXR image" + take_message(err));
  return std::string(reinterpret_cast<const char*>(memory), size);
}

void write_exr(const std::string& path, const RgbImage& image) {
  write_file_atomically(path, encode_exr(image, false, path));
}

}  // namespace pt
