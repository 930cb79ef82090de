// Statistics of rendered films for the stability tests: the image's mean
// illuminance with its standard error, the per-sample variance averaged over
// pixels, and a two-sided z-test of two images' means. They read the film's
// per-pixel variance of the mean (Film::variance), so pixels are the
// independent units and no test needs repeated renders.
#pragma once

#include <string>

#include "kernels/film.h"

namespace pt::test {

/// Mean over pixels of the pixels' mean illuminance, and its standard error
/// sqrt(sum of the pixels' variances of the mean) / pixels.
struct ImageMean {
  double mean = 0.0;
  double standard_error = 0.0;
};
ImageMean image_mean(const Film& film);

/// Average over pixels of the variance of one sample's illuminance
/// (variance of the mean x samples): what one more sample costs in noise.
double per_sample_variance(const Film& film);

/// z = (mean(a) - mean(b)) / sqrt(se(a)^2 + se(b)^2), approximately standard
/// normal when both films estimate the same image (many pixels and samples).
double mean_difference_z(const Film& a, const Film& b);

/// Two-sided z bound with false-alarm probability 1e-5 under the normal approximation.
inline constexpr double kZ1e5 = 4.42;

/// Stouffer's combined score over pixels with noise: sum of the per-pixel
/// z = (Y_a - Y_b) / sqrt(var_a + var_b), divided by sqrt(count). Standard
/// normal when a and b estimate the same image; unlike the image mean it is
/// not drowned by a few very noisy pixels (the edges of a visible light).
double stouffer_z(const Film& a, const Film& b);

/// Asserts that a and b estimate the same image: |stouffer_z| < 5 (two-sided
/// false alarm 6e-7), and per pixel (|z| > 3.29 in at most N * 0.001 +
/// 5 sqrt(N * 0.001) pixels: false alarm < 1e-6 for independent pixels; none
/// beyond 6.5: Bonferroni at 1e-10 / N). Nonfatal; prints the statistics.
void expect_same_image_within_noise(const Film& a, const Film& b, const std::string& what);

/// A copy of `film` with every radiance multiplied by `factor` (power checks).
Film scaled_film(const Film& film, float factor);

}  // namespace pt::test
