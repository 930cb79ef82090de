// Writes a Film: PNG with the course renderer's encoding
// (clamp((L * sqrt 2)^(1/2.2)) to 8 bits, top row first), PFM (linear float
// RGB, for error measurement) or OpenEXR (linear RGB, float or half: for
// Blender's compositor and other HDR tools) chosen by the file extension, and
// the sample-rate image. Every write is atomic.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "kernels/render/film.h"

namespace pt {

enum class ImageFormat { kPng, kPfm, kExr };

/// The pixel type of an OpenEXR output: 32-bit float or 16-bit half.
enum class ExrPixel { kFloat, kHalf };

/// By extension: ".pfm" -> PFM, ".exr" -> OpenEXR, anything else -> PNG.
ImageFormat image_format_for(const std::filesystem::path& path);

/// out.png -> out_rate.png (the sample-rate image beside an output).
std::filesystem::path rate_image_path(const std::filesystem::path& output);

/// How an encoded value in [0, 1] becomes 8 bits: to the nearest code (the
/// default, unbiased), or truncated as the course renderer does (which makes
/// its PNGs about 0.8% darker in linear terms at mid grey).
enum class PngQuantization { kNearest, kTruncate };

/// 8-bit value of one linear channel in the course renderer's encoding.
uint8_t encode_channel(float linear, PngQuantization q = PngQuantization::kNearest);

/// Colour of the sample-rate image for `samples` of at most `max_samples`:
/// blue (0) to green (0.5) to red (1).
void sample_rate_rgb8(uint32_t samples, uint32_t max_samples, uint8_t rgb[3]);

void write_image(const std::filesystem::path& path, const Film& film, PngQuantization q = PngQuantization::kNearest,
                 ExrPixel exr = ExrPixel::kFloat);
void write_sample_rate_image(const std::filesystem::path& path, const Film& film);
/// The bytes write_image and write_sample_rate_image write (the format by `path`'s extension).
std::string encode_image(const std::filesystem::path& path, const Film& film, PngQuantization q,
                         ExrPixel exr = ExrPixel::kFloat);
std::string encode_sample_rate_image(const Film& film);
/// Each pixel's variance of its mean illuminance as a grey PFM (for references).
void write_variance_image(const std::filesystem::path& path, const Film& film);
/// A grey PFM of `values` (width * height, row 0 at the top), e.g. each pixel's estimated RMSE.
void write_grey_pfm(const std::filesystem::path& path, int width, int height, const std::vector<float>& values);

/// Linear RGB image file contents (exposed for tests).
std::string encode_png_rgb8(int width, int height, const std::vector<uint8_t>& rgb);
std::string encode_pfm(int width, int height, const std::vector<float3>& top_down_rgb);

/// Reads a PFM written by encode_pfm (3 channels, little endian). Throws InputError.
std::vector<float3> read_pfm(const std::filesystem::path& path, int& width, int& height);

}  // namespace pt
