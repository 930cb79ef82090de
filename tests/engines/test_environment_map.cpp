// The environment light (kernels/scene/environment_map.h) and its EXR input
// (io/exr_image.h), on small maps made in code: a constant map, one bright
// texel (1000) among dim ones (0.01), a smooth gradient and an all-black map.
//
// EXR: write_exr -> read_exr round-trips float32 texels bit for bit; random
// bytes, a truncated file, a directory, a missing file, forged sizes and
// NaN / infinite / negative texels are refused with the path in the message.
// Lookup: exact at texel centres, against an independent bilinear
// interpolation (1e-5 relative), constant maps stay constant, the seam at
// phi = 0 / 2 pi is continuous. Sampling: the pdf integrates to 1 (1e-3,
// piecewise Gauss-Legendre quadrature split at half-texel boundaries, exact
// for the piecewise-constant pdf), sample() agrees with pdf() and radiance(),
// texel probabilities follow the dilated luminance times sin(theta), the
// pdf is positive wherever radiance is, chi-square goodness of fit of
// sample() against pdf() (2^20 samples, 16 x 32 bins in (cos theta, phi),
// bins expecting < 5 pooled, significance level 1e-3: with 511 (48 for the
// bright texel's, most bins pooled) degrees of freedom a noncentrality of 171
// (66) is rejected with probability 0.95, so a density off by 1.3% (0.8%) of
// itself in every bin is detected) and an importance-sampled hemisphere
// integral against quadrature within 4 standard errors (detects 1.2%).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "io/exr_image.h"
#include "io/scene_error.h"
#include "kernels/scene/environment_map.h"
#include "kernels/math/sampling.h"
#include "support/sampling_histogram.h"
#include "support/run_process.h"
#include "support/statistics.h"
#include "support/test_support.h"

namespace pt {
namespace {

using test::UniformSource;
constexpr double kPiD = std::numbers::pi;
constexpr int kChiSquareSamples = 1 << 20;
/// Chi-square significance level: a correct sampler fails with probability 1e-3 over the seed.
constexpr double kAlpha = 1e-3;

// ---------------------------------------------------------------- maps

std::vector<float3> constant_texels(int w, int h, float3 c) { return std::vector<float3>(size_t(w) * h, c); }

std::vector<float3> bright_texel_texels(int w, int h, int bi, int bj, float dim) {
  std::vector<float3> t = constant_texels(w, h, float3(dim));
  t[size_t(bj) * w + bi] = float3(1000.0f);
  return t;
}

std::vector<float3> gradient_texels(int w, int h) {
  std::vector<float3> t(size_t(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      t[size_t(j) * w + i] = {0.1f + 4.0f * i / w, 0.05f + 2.0f * j / h, 0.3f + float(i + j) / (w + h)};
  return t;
}

// The single bright texel sits in column 0 so that its neighbourhood wraps to column w - 1.
constexpr int kBw = 16, kBh = 8, kBi = 0, kBj = 2;
constexpr int kGw = 32, kGh = 16;

EnvironmentMap bright_map() { return {kBw, kBh, bright_texel_texels(kBw, kBh, kBi, kBj, 0.01f)}; }
EnvironmentMap gradient_map() { return {kGw, kGh, gradient_texels(kGw, kGh)}; }

// ---------------------------------------------------------------- geometry and quadrature

/// The mapping of docs/rendering.md inverted, in double: theta from +Y, phi as atan2(-z, x) + pi.
float3 dir_at(double theta, double phi) {
  return {float(-std::sin(theta) * std::cos(phi)), float(std::cos(theta)), float(std::sin(theta) * std::sin(phi))};
}

std::vector<double> breaks(double a, double b, double step) {
  std::vector<double> out{a};
  for (double k = std::floor(a / step) + 1; k * step < b - 1e-12; ++k)
    if (k * step > a + 1e-12) out.push_back(k * step);
  out.push_back(b);
  return out;
}

/// Integral of f(theta, phi) over [t0, t1] x [p0, p1] in solid angle
/// (sin(theta) dtheta dphi), split at every multiple of dt and dp (where f
/// may jump or kink) with 4-point Gauss-Legendre on each piece: exact for
/// f sin(theta) constant or polynomial of degree <= 7 per piece.
double integrate(const std::function<double(double, double)>& f, double t0, double t1, double p0, double p1, double dt,
                 double dp) {
  static constexpr double kNode[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  static constexpr double kWeight[4] = {0.3478548451374638, 0.6521451548625461, 0.6521451548625461, 0.3478548451374638};
  const std::vector<double> ts = breaks(t0, t1, dt), ps = breaks(p0, p1, dp);
  double sum = 0.0;
  for (size_t a = 0; a + 1 < ts.size(); ++a)
    for (size_t b = 0; b + 1 < ps.size(); ++b) {
      const double tm = 0.5 * (ts[a] + ts[a + 1]), th = 0.5 * (ts[a + 1] - ts[a]);
      const double pm = 0.5 * (ps[b] + ps[b + 1]), ph = 0.5 * (ps[b + 1] - ps[b]);
      for (int k = 0; k < 4; ++k)
        for (int l = 0; l < 4; ++l) {
          const double t = tm + th * kNode[k], p = pm + ph * kNode[l];
          sum += kWeight[k] * kWeight[l] * th * ph * f(t, p) * std::sin(t);
        }
    }
  return sum;
}

/// Integral over the sphere, split at half-texel boundaries of `m`.
double integrate_sphere(const EnvironmentMap& m, const std::function<double(double, double)>& f) {
  return integrate(f, 0, kPiD, 0, 2 * kPiD, kPiD / (2 * m.height()), kPiD / m.width());
}

/// sin(theta) of a direction as the test computes it (double).
double sin_theta_of(const float3& d) {
  const double r = std::hypot(double(d.x), double(d.z));
  return r / std::hypot(r, double(d.y));
}

// ---------------------------------------------------------------- EXR files

using test::ScratchDir;

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

/// read_exr(path) throws InputError whose message names the path and contains `what`.
void expect_refused(const std::string& path, const std::string& what) {
  try {
    read_exr(path);
    ADD_FAILURE() << path << " was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << "expected \"" << what << "\" in: " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

RgbImage random_image(int w, int h, uint32_t seed) {
  UniformSource u(seed);
  RgbImage img{w, h, {}};
  for (int k = 0; k < w * h; ++k) {
    // Spread over many binades, with exact zeros and subnormal-free tiny values.
    float3 t{u.next(), u.next(), u.next()};
    img.texels.push_back(t * std::exp2(std::floor(40.0f * u.next()) - 20.0f));
  }
  img.texels[1] = float3(0.0f);
  return img;
}

TEST(ExrImage, WriteThenReadRoundTripsFloat32TexelsExactly) {
  ScratchDir dir;
  for (auto [w, h] : {std::pair{5, 3}, std::pair{37, 23}}) {  // uncompressed and ZIP
    const RgbImage img = random_image(w, h, 7 + w);
    const std::string path = dir / ("map" + std::to_string(w) + ".exr");
    write_exr(path, img);
    const RgbImage back = read_exr(path);
    ASSERT_EQ(back.width, w);
    ASSERT_EQ(back.height, h);
    ASSERT_EQ(back.texels.size(), img.texels.size());
    for (size_t i = 0; i < img.texels.size(); ++i)
      ASSERT_TRUE(back.texels[i] == img.texels[i]) << "texel " << i << " of " << w << " x " << h;
  }
}

TEST(ExrImage, MalformedMissingAndSpecialFilesAreRefusedNamingThePath) {
  ScratchDir dir;
  const std::string good = dir / "good.exr";
  write_exr(good, random_image(20, 10, 3));
  const std::string bytes = test::file_bytes(good);

  UniformSource u(99);
  std::string noise(4096, '\0');
  for (char& c : noise) c = static_cast<char>(static_cast<unsigned char>(u.next() * 256));
  write_bytes(dir / "noise.exr", noise);
  expect_refused(dir / "noise.exr", "not an OpenEXR image");

  // Random bytes after a valid magic number and version.
  write_bytes(dir / "noise_after_magic.exr", bytes.substr(0, 8) + noise);
  expect_refused(dir / "noise_after_magic.exr", "EXR");

  for (size_t keep : {bytes.size() / 2, bytes.size() - 7, size_t(40)}) {
    const std::string path = dir / ("truncated" + std::to_string(keep) + ".exr");
    write_bytes(path, bytes.substr(0, keep));
    expect_refused(path, "EXR");
  }
  write_bytes(dir / "empty.exr", "");
  expect_refused(dir / "empty.exr", "not an OpenEXR image");
  std::filesystem::create_directory(dir / "a_directory.exr");
  expect_refused(dir / "a_directory.exr", "is a directory");
  expect_refused(dir / "missing.exr", "no such file");
}

/// The 16 bytes of the dataWindow attribute (min_x, min_y, max_x, max_y, little-endian).
size_t data_window_offset(const std::string& exr) {
  const std::string key("dataWindow\0box2i\0", 17);
  const size_t at = exr.find(key);
  EXPECT_NE(at, std::string::npos);
  return at + key.size() + 4;
}

TEST(ExrImage, ForgedEmptyAndAbsurdSizesAreRefusedBeforeDecoding) {
  ScratchDir dir;
  write_exr(dir / "small.exr", random_image(4, 4, 5));
  const std::string bytes = test::file_bytes(dir / "small.exr");
  const size_t at = data_window_offset(bytes);
  auto forge = [&](const std::string& name, int32_t max_x, int32_t max_y) {
    std::string b = bytes;
    std::memcpy(&b[at + 8], &max_x, 4);
    std::memcpy(&b[at + 12], &max_y, 4);
    write_bytes(dir / name, b);
    return dir / name;
  };
  expect_refused(forge("huge.exr", 99999, 99999), "exceeds");
  expect_refused(forge("empty_window.exr", -1, 3), "0 x 4 is empty");
}

TEST(ExrImage, NonFiniteAndNegativeTexelsAreRefusedNamingTheTexel) {
  ScratchDir dir;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  struct Case {
    const char* name;
    float3 value;
    const char* what;
  };
  for (const Case& c : {Case{"nan.exr", {1, nan, 1}, "texel (3, 1) is not finite"},
                        Case{"inf.exr", {inf, 1, 1}, "texel (3, 1) is not finite"},
                        Case{"negative.exr", {1, 1, -0.5f}, "texel (3, 1) is negative"}}) {
    RgbImage img = random_image(6, 4, 11);
    img.texels[1 * 6 + 3] = c.value;
    write_exr(dir / c.name, img);
    expect_refused(dir / c.name, c.what);
  }
}

TEST(ExrImage, WritingAnEmptyOrInconsistentImageThrows) {
  ScratchDir dir;
  EXPECT_THROW(write_exr(dir / "a.exr", RgbImage{0, 0, {}}), InputError);
  EXPECT_THROW(write_exr(dir / "b.exr", RgbImage{2, 2, {float3(1.0f)}}), InputError);
  EXPECT_THROW(write_exr(dir / "no_such_dir" / "c.exr", random_image(2, 2, 1)), InputError);
}

TEST(ExrImage, AReadMapBuildsAnEnvironmentMap) {
  ScratchDir dir;
  write_exr(dir / "g.exr", RgbImage{kGw, kGh, gradient_texels(kGw, kGh)});
  RgbImage img = read_exr(dir / "g.exr");
  EnvironmentMap m(img.width, img.height, std::move(img.texels));
  EXPECT_TRUE(m.lookup(2.5f, 3.5f) == gradient_texels(kGw, kGh)[3 * kGw + 2]);
}

// ---------------------------------------------------------------- lookup

TEST(EnvironmentLookup, ExactAtTexelCentresAndAlongDirectionsToThem) {
  const std::vector<float3> t = gradient_texels(kGw, kGh);
  const EnvironmentMap m = gradient_map();
  for (int j = 0; j < kGh; ++j)
    for (int i = 0; i < kGw; ++i) {
      const float3 expect = t[size_t(j) * kGw + i];
      ASSERT_TRUE(m.lookup(i + 0.5f, j + 0.5f) == expect) << i << ", " << j;
      // A float direction lands within ~1e-6 texels of the centre: the value within 1e-5 relative.
      const float3 d = dir_at(kPiD * (j + 0.5) / kGh, 2 * kPiD * (i + 0.5) / kGw);
      const float3 got = m.radiance(d);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(got[c], expect[c], 1e-5 * expect[c]) << i << ", " << j;
    }
}

/// Bilinear interpolation between texel centres written independently (floor-based, double).
double reference_bilinear(const std::vector<float3>& t, int w, int h, double x, double y, int c) {
  const double fx = x - 0.5, fy = y - 0.5;
  const int i0 = int(std::floor(fx)), j0 = int(std::floor(fy));
  const double tx = fx - i0, ty = fy - j0;
  auto at = [&](int i, int j) {
    i = ((i % w) + w) % w;
    j = std::clamp(j, 0, h - 1);
    return double(t[size_t(j) * w + i][c]);
  };
  return (1 - ty) * ((1 - tx) * at(i0, j0) + tx * at(i0 + 1, j0)) +
         ty * ((1 - tx) * at(i0, j0 + 1) + tx * at(i0 + 1, j0 + 1));
}

TEST(EnvironmentLookup, AgreesWithAnIndependentBilinearInterpolationWrappingAndClamping) {
  const std::vector<float3> t = gradient_texels(kGw, kGh);
  const EnvironmentMap m = gradient_map();
  UniformSource u(5);
  for (int k = 0; k < 20000; ++k) {
    const float x = u.next() * kGw, y = u.next() * kGh;
    const float3 got = m.lookup(x, y);
    for (int c = 0; c < 3; ++c) {
      const double want = reference_bilinear(t, kGw, kGh, x, y, c);
      ASSERT_NEAR(got[c], want, 1e-5 * want) << "x " << x << " y " << y;
    }
  }
  // Edges: x = 0 and x = width average columns w - 1 and 0; y = 0 and y = height clamp.
  for (float y : {0.0f, 0.25f, 7.5f, float(kGh)})
    for (int c = 0; c < 3; ++c) {
      const double want = reference_bilinear(t, kGw, kGh, 0.0, y, c);
      EXPECT_NEAR(m.lookup(0.0f, y)[c], want, 1e-5 * want);
      EXPECT_TRUE(m.lookup(0.0f, y) == m.lookup(float(kGw), y));
    }
}

TEST(EnvironmentLookup, ConstantMapIsConstantEverywhere) {
  const float3 c{0.7f, 1.3f, 2.9f};
  const EnvironmentMap m(9, 5, constant_texels(9, 5, c));
  UniformSource u(8);
  for (int k = 0; k < 20000; ++k) {
    Vec3T<float> s = sample_uniform_sphere(u.next(), u.next());
    const float3 got = m.radiance({s.x, s.y, s.z});
    for (int i = 0; i < 3; ++i) ASSERT_NEAR(got[i], c[i], 1e-6 * c[i]);
  }
  for (const float3& d : {float3{0, 1, 0}, float3{0, -1, 0}, float3{-1, 0, 0}, float3{-1, 0, -0.0f}})
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(m.radiance(d)[i], c[i], 1e-6 * c[i]);
}

TEST(EnvironmentLookup, ContinuousAcrossTheSeamAtPhiZero) {
  const EnvironmentMap m = gradient_map();
  // phi = atan2(-z, x) + pi is 0 / 2 pi along -x: step across it in z.
  for (double theta : {0.3, 1.2, 2.5})
    for (double eps : {1e-3, 1e-5}) {
      const float3 a = m.radiance(dir_at(theta, eps)), b = m.radiance(dir_at(theta, 2 * kPiD - eps));
      const float3 seam = m.lookup(0.0f, float(theta / kPiD * kGh));
      for (int c = 0; c < 3; ++c) {
        // The lookup changes by at most (largest column step) * eps * width / (2 pi).
        const double slope = 4.0 + 1.0;
        EXPECT_NEAR(a[c], seam[c], slope * eps * kGw / (2 * kPiD) + 1e-5);
        EXPECT_NEAR(b[c], seam[c], slope * eps * kGw / (2 * kPiD) + 1e-5);
      }
    }
  EXPECT_TRUE(is_black(m.radiance({0, 0, 0})));
  EXPECT_TRUE(is_black(m.radiance({std::numeric_limits<float>::quiet_NaN(), 1, 0})));
}

// ---------------------------------------------------------------- sampling

struct NamedMap {
  const char* name;
  EnvironmentMap map;
};

std::vector<NamedMap> all_maps() {
  return {{"constant", EnvironmentMap(12, 6, constant_texels(12, 6, float3(0.5f)))},
          {"bright texel", bright_map()},
          {"gradient", gradient_map()},
          {"black", EnvironmentMap(10, 7, constant_texels(10, 7, float3(0.0f)))},
          {"1 x 1", EnvironmentMap(1, 1, {float3(2.0f)})}};
}

TEST(EnvironmentSampling, PdfIntegratesToOneOverTheSphere) {
  for (const NamedMap& nm : all_maps()) {
    const double total = integrate_sphere(nm.map, [&](double t, double p) { return nm.map.pdf(dir_at(t, p)); });
    EXPECT_NEAR(total, 1.0, 1e-3) << nm.name;
  }
}

TEST(EnvironmentSampling, SampleAgreesWithPdfAndRadiance) {
  for (const NamedMap& nm : all_maps()) {
    UniformSource u(17);
    std::vector<std::pair<float, float>> us{
        {0, 0}, {0x1.fffffep-1f, 0x1.fffffep-1f}, {1.0f, 1.0f}, {0, 0x1.fffffep-1f}, {-0.5f, 2.0f}};
    for (int k = 0; k < 20000; ++k) us.emplace_back(u.next(), u.next());
    for (auto [u1, u2] : us) {
      const EnvironmentMap::Sample s = nm.map.sample(u1, u2);
      ASSERT_TRUE(is_finite(s.wi) && std::isfinite(s.pdf) && is_finite(s.radiance))
          << nm.name << " u " << u1 << " " << u2;
      ASSERT_NEAR(length(s.wi), 1.0f, 1e-5f) << nm.name;
      ASSERT_TRUE(s.radiance == nm.map.radiance(s.wi)) << nm.name;
      if (sin_theta_of(s.wi) < 1e-4) continue;
      const float p = nm.map.pdf(s.wi);
      ASSERT_GT(s.pdf, 0.0f) << nm.name;
      ASSERT_NEAR(s.pdf, p, 1e-4 * p) << nm.name;
    }
  }
}

/// Expected probability of each texel from the contract, computed here:
/// max luminance over the 3 x 3 neighbourhood (x wraps, y clamps) times
/// sin(theta at the row centre), normalised (uniform x sin if all black).
std::vector<double> expected_texel_probabilities(const std::vector<float3>& t, int w, int h) {
  std::vector<double> p(size_t(w) * h);
  double total = 0.0;
  for (int pass = 0; pass < 2 && total == 0.0; ++pass)
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        double m = 0.0;
        for (int dj = -1; dj <= 1; ++dj)
          for (int di = -1; di <= 1; ++di)
            m = std::max(m, double(illuminance(t[size_t(std::clamp(j + dj, 0, h - 1)) * w + (i + di + w) % w])));
        if (pass == 1) m = 1.0;
        p[size_t(j) * w + i] = m * std::sin(kPiD * (j + 0.5) / h);
        total += p[size_t(j) * w + i];
      }
  for (double& v : p) v /= total;
  return p;
}

TEST(EnvironmentSampling, TexelProbabilitiesFollowDilatedLuminanceTimesSinTheta) {
  struct Case {
    const char* name;
    int w, h;
    std::vector<float3> t;
  };
  std::vector<float3> lone = bright_texel_texels(kBw, kBh, kBi, kBj, 0.0f);
  for (const Case& c :
       {Case{"bright texel", kBw, kBh, bright_texel_texels(kBw, kBh, kBi, kBj, 0.01f)},
        Case{"bright texel on black", kBw, kBh, lone}, Case{"gradient", kGw, kGh, gradient_texels(kGw, kGh)},
        Case{"black", 10, 7, constant_texels(10, 7, float3(0.0f))}}) {
    const EnvironmentMap m(c.w, c.h, c.t);
    const std::vector<double> want = expected_texel_probabilities(c.t, c.w, c.h);
    for (int j = 0; j < c.h; ++j)
      for (int i = 0; i < c.w; ++i) {
        const float3 d = dir_at(kPiD * (j + 0.5) / c.h, 2 * kPiD * (i + 0.5) / c.w);
        const double p = m.pdf(d) * 2 * kPiD * kPiD * sin_theta_of(d) / (double(c.w) * c.h);
        // Float CDFs: differences of values in [0, 1] carry up to ~2^-24 absolute error.
        EXPECT_NEAR(p, want[size_t(j) * c.w + i], 1e-5 * want[size_t(j) * c.w + i] + 2 * 0x1p-24)
            << c.name << " texel " << i << ", " << j;
      }
  }
}

// Unbiased light sampling needs pdf > 0 wherever radiance > 0: the texels
// around a lone bright texel see it through the bilinear lookup.
TEST(EnvironmentSampling, PdfIsPositiveWhereverRadianceIs) {
  const EnvironmentMap m(kBw, kBh, bright_texel_texels(kBw, kBh, kBi, kBj, 0.0f));
  int lit = 0;
  for (int a = 1; a < 400; ++a)
    for (int b = 0; b < 800; ++b) {
      const float3 d = dir_at(kPiD * a / 400, 2 * kPiD * (b + 0.5) / 800);
      if (is_black(m.radiance(d))) { continue; }
      ++lit;
      ASSERT_GT(m.pdf(d), 0.0f) << "theta " << kPiD * a / 400 << " phi " << 2 * kPiD * (b + 0.5) / 800;
    }
  EXPECT_GT(lit, 400 * 800 / (kBw * kBh) * 3) << "the lit region spans about 4 texels of 128";
}

/// Chi-square test of sample() against pdf(): directions binned in
/// (cos theta, phi) of the map's own frame (pole +Y, phi = atan2(-z, x) + pi).
test::ChiSquareResult chi_square(const EnvironmentMap& sampled, const EnvironmentMap& density, uint32_t seed) {
  test::DirectionHistogram hist(16, 32, -1.0);
  UniformSource u(seed);
  for (int k = 0; k < kChiSquareSamples; ++k) {
    const float3 d = sampled.sample(u.next(), u.next()).wi;
    // (-x, z, y): the histogram's atan2(b, a) is then atan2(z, -x) = atan2(-z, x) + pi.
    hist.add(-d.x, d.z, d.y);
  }
  const auto mass = [&](double z0, double z1, double p0, double p1) {
    return integrate([&](double t, double p) { return density.pdf(dir_at(t, p)); }, std::acos(z1), std::acos(z0), p0,
                     p1, kPiD / (2 * density.height()), kPiD / density.width());
  };
  const std::vector<double> expected = hist.expected(kChiSquareSamples, mass);
  return test::chi_square_test(hist.counts(), expected);
}

TEST(EnvironmentSampling, ChiSquareAgainstPdfSingleBrightTexel) {
  const EnvironmentMap m = bright_map();
  const test::ChiSquareResult r = chi_square(m, m, 31);
  std::printf("bright texel: %s\n", r.summary.c_str());
  EXPECT_GT(r.p_value, kAlpha) << r.summary;
}

TEST(EnvironmentSampling, ChiSquareAgainstPdfGradient) {
  const EnvironmentMap m = gradient_map();
  const test::ChiSquareResult r = chi_square(m, m, 37);
  std::printf("gradient: %s\n", r.summary.c_str());
  EXPECT_GT(r.p_value, kAlpha) << r.summary;
}

// Power: the test must reject a density that is not the sampler's (the
// gradient against the same gradient mirrored top to bottom).
TEST(EnvironmentSampling, ChiSquareRejectsAWrongDensity) {
  std::vector<float3> t = gradient_texels(kGw, kGh), flipped(t.size());
  for (int j = 0; j < kGh; ++j)
    for (int i = 0; i < kGw; ++i) flipped[size_t(kGh - 1 - j) * kGw + i] = t[size_t(j) * kGw + i];
  const test::ChiSquareResult r = chi_square(gradient_map(), EnvironmentMap(kGw, kGh, flipped), 41);
  EXPECT_LT(r.p_value, 1e-6) << r.summary;
}

// With one texel of 1000 among 0.01s its 3 x 3 neighbourhood (which the
// bilinear lookup lets it light) carries ~99.99% of the weight: the sampled
// fractions inside that block and inside the texel itself match the
// fractions the weights give within 5 binomial standard errors, and > 99% land in the block.
// 2^20 samples: the texel's fraction (0.117) is checked to 5 SE of 0.27% of it,
// so a 1.8% bias fails with probability 0.95; the block's (1 - 1.05e-4) to an
// absolute 7e-5.
TEST(EnvironmentSampling, SamplesConcentrateWhereTheBrightTexelIs) {
  const EnvironmentMap m = bright_map();
  const std::vector<double> p = expected_texel_probabilities(bright_texel_texels(kBw, kBh, kBi, kBj, 0.01f), kBw, kBh);
  auto in_block = [](int i, int j) {
    const int di = std::min((i - kBi + kBw) % kBw, (kBi - i + kBw) % kBw);
    return di <= 1 && std::abs(j - kBj) <= 1;
  };
  double want_block = 0.0;
  for (int j = 0; j < kBh; ++j)
    for (int i = 0; i < kBw; ++i)
      if (in_block(i, j)) want_block += p[size_t(j) * kBw + i];
  const double want_texel = p[size_t(kBj) * kBw + kBi];

  const int n = 1 << 20;
  int block = 0, texel = 0;
  UniformSource u(43);
  for (int k = 0; k < n; ++k) {
    const float3 d = m.sample(u.next(), u.next()).wi;
    float x, y, s;
    ASSERT_TRUE(m.image_coordinates(d, x, y, s));
    const int i = std::min(int(x), kBw - 1), j = std::min(int(y), kBh - 1);
    block += in_block(i, j);
    texel += i == kBi && j == kBj;
  }
  const double f_block = double(block) / n, f_texel = double(texel) / n;
  EXPECT_GT(f_block, 0.99);
  EXPECT_NEAR(f_block, want_block, 5 * std::sqrt(want_block * (1 - want_block) / n) + 1e-6);
  EXPECT_NEAR(f_texel, want_texel, 5 * std::sqrt(want_texel * (1 - want_texel) / n));
  std::printf("block %.6f (expected %.6f), texel %.4f (expected %.4f)\n", f_block, want_block, f_texel, want_texel);
}

// Irradiance-like integral of L cos(theta) over the upper hemisphere: the
// importance-sampled estimate against quadrature, |z| < 4 (two-sided 6e-5),
// with SE below 0.35% of it, so that a 2% bias fails with probability 0.95
// (4 + 1.645 SE); measured SE 0.22%: a 1.2% bias (and z = 1.0, 0.9, -0.3 for three seeds at 2^24 samples).
TEST(EnvironmentSampling, ImportanceSampledHemisphereIntegralMatchesQuadrature) {
  const EnvironmentMap m = gradient_map();
  const double exact =
      integrate([&](double t, double p) { return double(illuminance(m.radiance(dir_at(t, p)))) * std::cos(t); }, 0,
                kPiD / 2, 0, 2 * kPiD, kPiD / (2 * kGh), kPiD / kGw);
  const int n = 1 << 19;
  std::vector<double> values(n);
  UniformSource u(47);
  for (int k = 0; k < n; ++k) {
    const EnvironmentMap::Sample s = m.sample(u.next(), u.next());
    values[k] = s.pdf > 0 && s.wi.y > 0 ? illuminance(s.radiance) * s.wi.y / s.pdf : 0.0;
  }
  const test::MeanError me = test::mean_and_error(values);
  EXPECT_LT(me.standard_error, 0.0035 * exact) << "too noisy to see a 2% bias";
  EXPECT_LT(std::fabs(test::z_score(me, exact)), 4.0)
      << "estimate " << me.mean << " +- " << me.standard_error << ", quadrature " << exact;
  std::printf("hemisphere: estimate %.6f +- %.6f, quadrature %.6f\n", me.mean, me.standard_error, exact);
}

}  // namespace
}  // namespace pt
