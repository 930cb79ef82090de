// Error of an image against a converged reference image: root mean squared
// error, relative MSE (pbrt's: squared error over reference^2 + 0.01) and
// mean bias, over all pixels and channels.
#pragma once

#include <vector>

#include "kernels/math/vec3.h"

namespace pt {

struct ErrorMetrics {
  double rmse = 0.0;
  double rel_mse = 0.0;
  double mean_bias = 0.0;
};

/// Both images have the same size (row-major linear RGB).
ErrorMetrics compare_images(const std::vector<float3>& image, const std::vector<float3>& reference);

}  // namespace pt
