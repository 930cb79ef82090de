// compare_images.
#include "image_metrics.h"

#include <cmath>

namespace pt {

ErrorMetrics compare_images(const std::vector<float3>& image, const std::vector<float3>& reference) {
  ErrorMetrics m;
  double se = 0.0, rel = 0.0, bias = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < image.size() && i < reference.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      double d = double(image[i][c]) - reference[i][c];
      se += d * d;
      rel += d * d / (double(reference[i][c]) * reference[i][c] + 0.01);
      bias += d;
      ++n;
    }
  if (n == 0) return m;
  m.rmse = std::sqrt(se / n);
  m.rel_mse = rel / n;
  m.mean_bias = bias / n;
  return m;
}

}  // namespace pt
