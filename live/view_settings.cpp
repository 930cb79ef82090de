// The view's settings against the command line's.
#include "view_settings.h"

#include <algorithm>
#include <cmath>

namespace pt::live {

// The fields a view holds as the render settings hold them: X(view's, settings').
// clang-format off
#define PT_VIEW_FIELDS(X)                        \
  X(samples, samples_per_pixel)                  \
  X(light_samples, light_samples)                \
  X(max_depth, max_depth)                        \
  X(adaptive_tolerance, adaptive_tolerance)      \
  X(adaptive_batch, adaptive_batch)              \
  X(bounces, bounces)                            \
  X(direct, direct)
// clang-format on

RenderSettings render_settings(const RenderSettings& base, const ViewSettings& v, int width, int height) {
  RenderSettings rs = base;
  rs.width = width;
  rs.height = height;
  rs.region.reset();
#define PT_TO_SETTINGS(view, settings) rs.settings = v.view;
  PT_VIEW_FIELDS(PT_TO_SETTINGS)
#undef PT_TO_SETTINGS
  rs.shading = v.display == Display::kNormals ? ShadingMode::kNormals : ShadingMode::kPathTrace;
  return rs;
}

ViewSettings view_settings_of(const RenderSettings& rs) {
  ViewSettings v;
  v.width = rs.width;
  v.height = rs.height;
#define PT_TO_VIEW(view, settings) v.view = rs.settings;
  PT_VIEW_FIELDS(PT_TO_VIEW)
#undef PT_TO_VIEW
  v.display = rs.shading == ShadingMode::kNormals ? Display::kNormals : Display::kImage;
  return v;
}

#undef PT_VIEW_FIELDS

std::string view_settings_problem(const ViewSettings& v) {
  auto range = [](const char* what, int64_t value, int64_t lo, int64_t hi) {
    return value < lo || value > hi ? std::string(what) + " must be from " + std::to_string(lo) + " to " +
                                          std::to_string(hi) + ", got " + std::to_string(value)
                                    : std::string();
  };
  std::string e;
  if (e.empty()) e = range("width", v.width, kMinViewSide, kMaxViewSide);
  if (e.empty()) e = range("height", v.height, kMinViewSide, kMaxViewSide);
  if (e.empty() && int64_t(v.width) * v.height > kMaxViewPixels)
    e = "the view may have at most " + std::to_string(kMaxViewPixels) + " pixels, got " + std::to_string(v.width) +
        " x " + std::to_string(v.height);
  if (e.empty()) e = range("samples", v.samples, 1, 1 << 24);
  if (e.empty()) e = range("light samples", v.light_samples, 1, 4096);
  if (e.empty()) e = range("maximum depth", v.max_depth, 0, 1024);
  if (e.empty()) e = range("adaptive batch", v.adaptive_batch, 1, 1 << 24);
  if (e.empty() && !(v.adaptive_tolerance >= 0.0f && std::isfinite(v.adaptive_tolerance)))
    e = "adaptive tolerance must be a finite number >= 0";
  if (e.empty() && std::find(kPreviewChoices.begin(), kPreviewChoices.end(), int(v.preview)) == kPreviewChoices.end())
    e = "preview must be 0 (automatic), 1, 2, 4 or 8";
  if (e.empty() &&
      (static_cast<size_t>(v.display) >= kDisplayNames.size() ||
       static_cast<size_t>(v.bounces) >= kBounceNames.size() || static_cast<size_t>(v.direct) >= kDirectNames.size()))
    e = "unknown display, bounce mode or direct-light estimator";
  return e;
}

}  // namespace pt::live
