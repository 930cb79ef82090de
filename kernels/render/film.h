// The film every engine renders into: per-pixel mean radiance and samples
// taken, row 0 at the top. Only pixels inside the render region are written.
// A film normally spans the whole image; one cropped to the region (asked for
// with RenderControl::crop_film, as tile renders do) spans only the region,
// its (x0, y0) being the region's corner in the image.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/render/render_settings.h"
#include "kernels/math/vec3.h"

namespace pt {

struct Film {
  int width = 0, height = 0;      ///< of the film (the image's, unless cropped)
  int x0 = 0, y0 = 0;             ///< image position of the film's top-left pixel
  uint32_t max_samples = 0;       ///< the -s limit, for the sample-rate image
  std::vector<float3> radiance;   ///< linear RGB mean per pixel
  std::vector<uint32_t> samples;  ///< camera samples taken per pixel
  std::vector<float> variance;    ///< variance of each pixel's mean illuminance (s^2 / n)

  Film() = default;
  // Defined once (film.cpp): a film is made and dropped by the engines of
  // every instruction-set level, and its members are no level's own.
  Film(const Film&);
  Film(Film&&) noexcept;
  Film& operator=(const Film&);
  Film& operator=(Film&&) noexcept;
  ~Film();
  Film(int w, int h, uint32_t max_spp)
      : width(w),
        height(h),
        max_samples(max_spp),
        radiance(size_t(w) * h),
        samples(size_t(w) * h, 0),
        variance(size_t(w) * h, 0.0f) {}
  /// A film covering only `area` of the image.
  static Film cropped(const Region& area, uint32_t max_spp) {
    Film f(area.width, area.height, max_spp);
    f.x0 = area.x;
    f.y0 = area.y;
    return f;
  }
  /// Index of image pixel (x, y).
  size_t index(int x, int y) const { return size_t(y - y0) * width + (x - x0); }
};

}  // namespace pt
