// Checks of a rendered film against a closed form, shared by the light-
// transport tests: pixels that all see the same radiance are independent
// estimates of it (each pixel draws its own random numbers), so their mean
// and standard error give a z-test; an exact answer is checked exactly.
#pragma once

#include <string>

#include "kernels/render/film.h"
#include "support/statistics.h"

namespace pt::test {

/// Mean and standard error over all pixels of one channel (0, 1, 2).
MeanError film_channel_mean(const Film& film, int channel);

/// Every pixel is an independent, unbiased estimate of `expected`: per channel,
/// |mean - expected| < kZ5 standard errors (false failure 5.7e-7 per channel).
/// The test must also detect a bias of `detectable_bias` (relative to
/// expected): the standard error must be at most detectable_bias / (kZ5 +
/// kZ95) of expected (0.30% for a 2% bias), so that a mean off by that much
/// lies beyond kZ5 standard errors with probability at least 0.95. An expected
/// channel of exactly 0 must be 0 in every pixel; an estimator without noise
/// (cosine sampling of a uniform sky) must be exact to 1e-6.
void expect_film_estimates(const Film& film, const float3& expected, const std::string& what,
                           double detectable_bias = 0.02);

/// Every pixel equals `expected` to `relative` accuracy per channel.
void expect_film_equals(const Film& film, const float3& expected, const std::string& what, double relative = 1e-6);

}  // namespace pt::test
