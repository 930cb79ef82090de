// PNG (through stb_image_write), PFM and the sample-rate colour map.
#include "image_output.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

#include "atomic_file.h"
#include "exr_image.h"
#include "read_file.h"
#include "scene_error.h"

namespace pt {

ImageFormat image_format_for(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".pfm" ? ImageFormat::kPfm : ext == ".exr" ? ImageFormat::kExr : ImageFormat::kPng;
}

std::filesystem::path rate_image_path(const std::filesystem::path& output) {
  std::filesystem::path p = output;
  p.replace_filename(output.stem().string() + "_rate.png");
  return p;
}

uint8_t encode_channel(float linear, PngQuantization q) {
  float v = std::pow(std::max(linear, 0.0f) * std::sqrt(2.0f), 1.0f / 2.2f);
  if (!(v >= 0.0f)) v = 0.0f;  // NaN
  v = std::min(v, 1.0f);
  return static_cast<uint8_t>(q == PngQuantization::kTruncate ? v * 255.0f : std::round(v * 255.0f));
}

std::string encode_png_rgb8(int width, int height, const std::vector<uint8_t>& rgb) {
  std::string out;
  auto sink = [](void* ctx, void* data, int size) {
    static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), static_cast<size_t>(size));
  };
  if (!stbi_write_png_to_func(sink, &out, width, height, 3, rgb.data(), width * 3))
    throw InputError("PNG encoding failed");
  return out;
}

std::string encode_pfm(int width, int height, const std::vector<float3>& rgb) {
  std::string header = "PF\n" + std::to_string(width) + " " + std::to_string(height) + "\n-1.0\n";
  std::string out = header;
  out.resize(header.size() + size_t(width) * height * 12);
  char* dst = out.data() + header.size();
  for (int y = height - 1; y >= 0; --y)  // PFM stores the bottom row first
    for (int x = 0; x < width; ++x) {
      const float3& c = rgb[size_t(y) * width + x];
      std::memcpy(dst, &c, 12);
      dst += 12;
    }
  return out;
}

std::string encode_image(const std::filesystem::path& path, const Film& film, PngQuantization q, ExrPixel exr) {
  if (image_format_for(path) == ImageFormat::kPfm) return encode_pfm(film.width, film.height, film.radiance);
  if (image_format_for(path) == ImageFormat::kExr)
    return encode_exr(RgbImage{film.width, film.height, film.radiance}, exr == ExrPixel::kHalf, path.string());
  std::vector<uint8_t> rgb(film.radiance.size() * 3);
  for (size_t i = 0; i < film.radiance.size(); ++i)
    for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = encode_channel(film.radiance[i][c], q);
  return encode_png_rgb8(film.width, film.height, rgb);
}

void write_image(const std::filesystem::path& path, const Film& film, PngQuantization q, ExrPixel exr) {
  write_file_atomically(path, encode_image(path, film, q, exr));
}

void sample_rate_rgb8(uint32_t samples, uint32_t max_samples, uint8_t rgb[3]) {
  float denom = static_cast<float>(std::max<uint32_t>(max_samples, 1));
  float r = std::clamp(samples / denom, 0.0f, 1.0f);
  float3 c = r < 0.5f ? float3{0.0f, 2.0f * r, 1.0f - 2.0f * r} : float3{2.0f * r - 1.0f, 2.0f - 2.0f * r, 0.0f};
  for (int k = 0; k < 3; ++k) rgb[k] = static_cast<uint8_t>(std::lround(c[k] * 255.0f));
}

std::string encode_sample_rate_image(const Film& film) {
  std::vector<uint8_t> rgb(film.samples.size() * 3);
  for (size_t i = 0; i < film.samples.size(); ++i) sample_rate_rgb8(film.samples[i], film.max_samples, &rgb[i * 3]);
  return encode_png_rgb8(film.width, film.height, rgb);
}

void write_sample_rate_image(const std::filesystem::path& path, const Film& film) {
  write_file_atomically(path, encode_sample_rate_image(film));
}

void write_variance_image(const std::filesystem::path& path, const Film& film) {
  std::vector<float3> grey(film.variance.size());
  for (size_t i = 0; i < grey.size(); ++i) grey[i] = float3(film.variance[i]);
  write_file_atomically(path, encode_pfm(film.width, film.height, grey));
}

void write_grey_pfm(const std::filesystem::path& path, int width, int height, const std::vector<float>& values) {
  std::vector<float3> grey(values.size());
  for (size_t i = 0; i < grey.size(); ++i) grey[i] = float3(values[i]);
  write_file_atomically(path, encode_pfm(width, height, grey));
}

std::vector<float3> read_pfm(const std::filesystem::path& path, int& width, int& height) {
  // A PFM of the largest image this program writes, and then some.
  std::string bytes = read_regular_file(path, "PFM image", uint64_t(1) << 36);
  std::istringstream in(bytes);
  std::string magic;
  float scale = 0;
  in >> magic >> width >> height >> scale;
  if (!in || magic != "PF" || width <= 0 || height <= 0 || width > 65536 || height > 65536 || !(scale < 0))
    throw InputError(path.string() + ": not a little-endian RGB PFM");
  in.get();
  // The header must not make us allocate more than the file holds.
  const uint64_t offset = static_cast<uint64_t>(in.tellg());
  const uint64_t row_bytes = uint64_t(width) * 12;
  if (bytes.size() - offset < row_bytes * uint64_t(height)) throw InputError(path.string() + ": PFM data is truncated");
  std::vector<float3> rgb(size_t(width) * height);
  for (int y = height - 1, row = 0; y >= 0; --y, ++row)
    std::memcpy(&rgb[size_t(y) * width], bytes.data() + offset + row * row_bytes, row_bytes);
  return rgb;
}

}  // namespace pt
