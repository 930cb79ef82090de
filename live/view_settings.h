// What the live page controls beyond the camera: the view's size, the -s, -l
// and -m of the command line, the CS184 debugging views (normal shading,
// bounce selections, the adaptive sample-rate image, hemisphere or light
// sampling) and the resolution while the camera moves. Everything else comes
// from the command line's settings unchanged, so a view renders as the
// command line does with the same flags.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "kernels/render/render_settings.h"

namespace pt::live {

/// What the image shows.
enum class Display : uint8_t {
  kImage,       ///< the render (path tracing)
  kNormals,     ///< normal shading (--normals)
  kSampleRate,  ///< samples taken / -s per pixel, blue to green to red (adaptive sampling's image)
};

inline constexpr std::array<const char*, 3> kDisplayNames = {"image", "normals", "rate"};
inline constexpr std::array<const char*, 4> kBounceNames = {"accumulate", "only-m", "direct", "indirect"};
inline constexpr std::array<const char*, 4> kDirectNames = {"light", "hemisphere", "cosine", "mis"};  // DirectLighting

/// The largest view: 4 Mpixels (a 2048 x 2048 view holds 200 MB of accumulators).
inline constexpr int64_t kMaxViewPixels = int64_t(1) << 22;
inline constexpr int kMinViewSide = 16, kMaxViewSide = 4096;
/// Resolution divisors while the camera moves: 0 = chosen per frame to keep 30 frames/s.
inline constexpr std::array<int, 5> kPreviewChoices = {0, 1, 2, 4, 8};

/// 32 bytes.
struct ViewSettings {
  int width = 800, height = 600;    ///< the view, and the Render button's image
  int samples = 1024;               ///< -s: samples per pixel the view accumulates to
  int light_samples = 1;            ///< -l
  int max_depth = 1;                ///< -m
  float adaptive_tolerance = 0.0f;  ///< -a's TOL (0: off)
  int adaptive_batch = 32;          ///< -a's BATCH
  Display display = Display::kImage;
  BounceMode bounces = BounceMode::kAccumulate;
  DirectLighting direct = DirectLighting::kMis;
  uint8_t preview = 0;  ///< resolution divisor while moving (kPreviewChoices)

  bool operator==(const ViewSettings&) const = default;
};
static_assert(sizeof(ViewSettings) == 32);

/// The command line's settings with the view's changes, at width x height.
RenderSettings render_settings(const RenderSettings& base, const ViewSettings& v, int width, int height);

/// The view's part of the command line's settings (its -r, -s, -l, -m, -a, --normals, --bounces, --direct).
ViewSettings view_settings_of(const RenderSettings& rs);

/// Why `v` cannot be rendered (a size, count or choice out of range), or "".
std::string view_settings_problem(const ViewSettings& v);

}  // namespace pt::live
