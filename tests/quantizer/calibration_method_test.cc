// Calibration methods on synthetic tensors whose answers are known analytically: the histogram
// (exact growth, quantiles), minmax, moving-average minmax, percentile, entropy (KL) and MSE,
// plus all-zero tensors, NaN/Inf activations and outlier-heavy tensors.

#include <cmath>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "support/random.h"
#include "tlvlink/quantize/calibration_method.h"
#include "tlvlink/quantize/observer.h"

namespace tlvlink::quantize {
namespace {

// n evenly spaced values covering [lo, hi] (a uniform distribution without sampling noise).
std::vector<float> uniform_grid(size_t n, float lo, float hi) {
  std::vector<float> v(n);
  for (size_t i = 0; i < n; ++i)
    v[i] = lo + (hi - lo) * static_cast<float>(i) / static_cast<float>(n - 1);
  return v;
}

TensorObserver observe_all(const std::vector<float>& values) {
  TensorObserver obs;
  EXPECT_TRUE(obs.observe(values, "t").ok());
  return obs;
}

// Mean squared error of quantizing `values` to 256 levels on [lo, hi] ∪ {0} (what the int8
// tensor would actually do), with round-to-nearest and saturation.
double fake_quant_mse(const std::vector<float>& values, float range_lo, float range_hi) {
  const double lo = std::min(static_cast<double>(range_lo), 0.0);
  const double hi = std::max(static_cast<double>(range_hi), 0.0);
  const double s = (hi - lo) / 255.0;
  const double zp = std::nearbyint(-128.0 - lo / s);
  double e = 0;
  for (float v : values) {
    const double q = std::clamp(std::nearbyint(static_cast<double>(v) / s) + zp, -128.0, 127.0);
    const double d = (q - zp) * s - static_cast<double>(v);
    e += d * d;
  }
  return e / static_cast<double>(values.size());
}

TEST(Histogram, GrowthMergesBinsExactlyAndKeepsEveryValue) {
  Histogram h;
  const std::vector<float> small = uniform_grid(1000, -0.9f, 0.9f);
  h.add(small);
  EXPECT_EQ(h.range(), 1.0);  // smallest power of two >= 0.9
  const double median_before = h.quantile(0.5);
  h.add(std::vector<float>{7.5f});  // forces R: 1 -> 8 (three doublings)
  EXPECT_EQ(h.range(), 8.0);
  EXPECT_EQ(h.total(), 1001u);
  EXPECT_EQ(std::accumulate(h.counts().begin(), h.counts().end(), uint64_t{0}), 1001u);
  // The merge is exact: the small values still split evenly around 0 at the coarser width.
  EXPECT_NEAR(h.quantile(0.5), median_before, h.bin_width());
  // x = R lands in the last bin rather than off the end.
  h.add(std::vector<float>{8.0f});
  EXPECT_EQ(h.counts().back(), 1u);
}

TEST(Histogram, QuantileOfAUniformGridIsLinear) {
  Histogram h;
  h.add(uniform_grid(100001, 0.0f, 1.0f));
  for (double q : {0.1, 0.5, 0.99, 0.9999}) EXPECT_NEAR(h.quantile(q), q, 2 * h.bin_width()) << q;
  EXPECT_EQ(Histogram().quantile(0.5), 0.0);
}

TEST(Observer, MinMaxAndMovingAverageFollowTheirDefinitions) {
  TensorObserver obs;
  const double c = 0.25;
  ASSERT_TRUE(obs.observe(std::vector<float>{-1.0f, 2.0f}, "t", c).ok());
  ASSERT_TRUE(obs.observe(std::vector<float>{-3.0f, 1.0f}, "t", c).ok());
  ASSERT_TRUE(obs.observe(std::vector<float>{0.0f, 6.0f}, "t", c).ok());
  EXPECT_EQ(obs.min, -3.0f);
  EXPECT_EQ(obs.max, 6.0f);
  // ema_1 = first frame; ema_k = ema_{k-1} + c (x_k - ema_{k-1}).
  const double emin = -1.0 + c * (-3.0 + 1.0), emax = 2.0 + c * (1.0 - 2.0);
  EXPECT_DOUBLE_EQ(obs.ema_min, emin + c * (0.0 - emin));
  EXPECT_DOUBLE_EQ(obs.ema_max, emax + c * (6.0 - emax));
  EXPECT_EQ(obs.zeros, 1u);
  CalibrationOptions o;
  o.method = CalibrationMethod::kMinMax;
  EXPECT_EQ(choose_range(obs, o).lo, -3.0f);
  EXPECT_EQ(choose_range(obs, o).hi, 6.0f);
  o.method = CalibrationMethod::kEma;
  EXPECT_FLOAT_EQ(choose_range(obs, o).lo, static_cast<float>(emin + c * (0.0 - emin)));
}

TEST(Observer, NonFiniteActivationIsAnErrorNamingTheTensor) {
  for (float bad : {std::numeric_limits<float>::infinity(), std::nanf("")}) {
    TensorObserver obs;
    const Status s = obs.observe(std::vector<float>{1.0f, bad}, "block3.expand");
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code(), ErrorCode::kNonFiniteValue);
    EXPECT_NE(std::string(s.error().message()).find("block3.expand"), std::string::npos);
  }
}

TEST(Percentile, CutsTheTailsOfAUniformDistribution) {
  const TensorObserver obs = observe_all(uniform_grid(200001, -2.0f, 2.0f));
  const Range r = percentile_range(obs, 99.0);
  // 1 % in each tail of U(-2, 2): +-1.96, within a histogram bin.
  const double tolerance = 2 * obs.histogram.bin_width();
  EXPECT_NEAR(r.lo, -1.96, tolerance);
  EXPECT_NEAR(r.hi, 1.96, tolerance);
  const Range all = percentile_range(obs, 100.0);
  EXPECT_EQ(all.lo, -2.0f);
  EXPECT_EQ(all.hi, 2.0f);
}

TEST(Entropy, KeepsTheFullRangeOfAUniformDistribution) {
  // Nothing to gain from clipping a flat density: every narrower candidate adds clipped mass.
  const TensorObserver obs = observe_all(uniform_grid(100001, 0.0f, 6.0f));
  const Range r = entropy_range(obs);
  EXPECT_EQ(r.lo, 0.0f);
  EXPECT_GT(r.hi, 0.97f * 6.0f);
  EXPECT_LE(r.hi, 6.0f);
}

// Half-normal |N(0,1)| values at their quantiles (no sampling noise).
std::vector<float> half_normal_grid(size_t n) {
  std::vector<float> v(n);
  for (size_t i = 0; i < n; ++i) {
    const double p = (static_cast<double>(i) + 0.5) / static_cast<double>(n);  // P(|x| < q)
    // Inverse of erf by bisection: |x| = sqrt(2) erfinv(p).
    double lo = 0, hi = 10;
    for (int k = 0; k < 60; ++k) {
      const double mid = 0.5 * (lo + hi);
      (std::erf(mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
    }
    v[i] = static_cast<float>(0.5 * (lo + hi));
  }
  return v;
}

TEST(Entropy, ClipsFarOutliersButKeepsTheBody) {
  // A ReLU-like half-normal body plus 5 values at 100 sigma: KL drops the outliers (their clipped
  // mass costs less than the resolution they would take from the body) but keeps the body.
  std::vector<float> v = half_normal_grid(100000);
  for (int i = 0; i < 5; ++i) v.push_back(100.0f);
  const Range r = entropy_range(observe_all(v));
  EXPECT_GE(r.lo, 0.0f);  // one-sided: the smallest value (the grid's first quantile, ~6e-6)
  EXPECT_LT(r.lo, 1e-3f);
  EXPECT_GE(r.hi, 3.0f);   // >= the body's 99.7th percentile
  EXPECT_LT(r.hi, 50.0f);  // the outliers are clipped
}

TEST(Mse, UniformDistributionClipsOnlyAFraction) {
  // For U(-A, A) the optimum of s^2/12 + clip error is ~0.997 A (derivative balance).
  const float a = 3.0f;
  const Range r = mse_range(observe_all(uniform_grid(100001, -a, a)));
  EXPECT_GT(r.hi, 0.98f * a);
  EXPECT_LT(r.lo, -0.98f * a);
}

// Expected squared error of N(0,1) quantized on [-alpha, alpha] with 255 steps (the model
// mse_range minimises), in closed form: rounding s^2/12 inside + 2 E[(|x| - alpha)^2; |x| > alpha].
double gaussian_error(double alpha) {
  const double s = 2 * alpha / 255.0;
  const double tail = 0.5 * std::erfc(alpha / std::sqrt(2.0));
  const double pdf = std::exp(-alpha * alpha / 2) / std::sqrt(2 * M_PI);
  return s * s / 12.0 * (1 - 2 * tail) + 2 * ((1 + alpha * alpha) * tail - alpha * pdf);
}

TEST(Mse, GaussianClipMatchesTheAnalyticOptimum) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> n(0.0f, 1.0f);
  std::vector<float> v(400000);
  for (float& x : v) x = n(rng);
  double best = 1, best_e = 1e9;
  for (double alpha = 1.0; alpha < 8.0; alpha += 0.001) {
    if (const double e = gaussian_error(alpha); e < best_e) {
      best_e = e;
      best = alpha;
    }
  }
  const Range r = mse_range(observe_all(v));
  // The search grid is max|x|/400 and the sample tail is finite: 5 % of the optimum (~3.9).
  constexpr double kRelTolerance = 0.05;
  EXPECT_NEAR(r.hi, best, kRelTolerance * best) << "analytic optimum " << best;
  EXPECT_NEAR(-r.lo, best, kRelTolerance * best);
}

TEST(Outliers, PercentileAndMseBeatMinMaxOnAnOutlierHeavyTensor) {
  // A Gaussian body plus two outliers at +-200 sigma in 1M values (e.g. a few saturated pixels
  // on one calibration frame). minmax spends its 255 steps on them (step 1.6 sigma), nearly
  // erasing the body; percentile and MSE clip them and keep resolution where the values are.
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> n(0.0f, 1.0f);
  std::vector<float> v(1000000);
  for (float& x : v) x = n(rng);
  v[1234] = 200.0f;
  v[56789] = -200.0f;
  const TensorObserver obs = observe_all(v);
  const Range p = percentile_range(obs, 99.99);
  const Range m = mse_range(obs);
  const Range e = entropy_range(obs);
  for (const auto& [name, r] : {std::pair{"percentile", p}, {"mse", m}, {"entropy", e}}) {
    SCOPED_TRACE(name);
    EXPECT_GE(r.hi, 3.0f);  // the body is kept, never clipped to nothing
    EXPECT_LE(r.lo, -3.0f);
  }
  // Percentile cuts at the body's 99.99th percentile (3.7 sigma). MSE balances the clipped
  // outliers' cost f (200 - a)^2 (f = 2e-6) against rounding (2a/255)^2/12: optimum a ~ 56.
  EXPECT_LT(p.hi, 5.0f);
  EXPECT_GT(p.lo, -5.0f);
  EXPECT_NEAR(m.hi, 56.0f, 5.0f);
  EXPECT_NEAR(m.lo, -56.0f, 5.0f);
  // On the tensor itself, outliers included, both beat minmax (~0.2 per value); MSE minimises
  // exactly this.
  const double minmax = fake_quant_mse(v, obs.min, obs.max);
  EXPECT_LT(fake_quant_mse(v, m.lo, m.hi), minmax);
  EXPECT_LT(fake_quant_mse(v, p.lo, p.hi), minmax);
  // On fresh values of the body (what most deployment frames look like): far better.
  std::vector<float> body(50000);
  for (float& x : body) x = n(rng);
  const double body_minmax = fake_quant_mse(body, obs.min, obs.max);
  EXPECT_LT(fake_quant_mse(body, p.lo, p.hi), 0.01 * body_minmax);
  EXPECT_LT(fake_quant_mse(body, m.lo, m.hi), 0.1 * body_minmax);
}

TEST(AllZero, EveryMethodGivesAFiniteZeroRange) {
  // A ReLU layer on black frames: the histogram holds only zeros.
  const TensorObserver obs = observe_all(std::vector<float>(4096, 0.0f));
  for (CalibrationMethod m : kAllCalibrationMethods) {
    CalibrationOptions o;
    o.method = m;
    const Range r = choose_range(obs, o);
    EXPECT_EQ(r.lo, 0.0f) << calibration_method_name(m);
    EXPECT_EQ(r.hi, 0.0f) << calibration_method_name(m);
  }
  EXPECT_EQ(expected_quantization_mse(obs, 0.0, 1.0), 0.0);  // exact zeros cost nothing
  // Never observed: empty range, no NaN.
  const Range none = choose_range(TensorObserver{}, CalibrationOptions{});
  EXPECT_EQ(none.lo, 0.0f);
  EXPECT_EQ(none.hi, 0.0f);
}

TEST(MethodNames, RoundTripAndRejectUnknown) {
  for (CalibrationMethod m : kAllCalibrationMethods) {
    auto parsed = parse_calibration_method(calibration_method_name(m));
    ASSERT_TRUE(parsed.ok());
    EXPECT_EQ(*parsed, m);
  }
  EXPECT_EQ(parse_calibration_method("kl").error().code(), ErrorCode::kInvalidArgument);
  CalibrationOptions bad;
  bad.percentile = 40;
  EXPECT_FALSE(validate(bad).ok());
}

}  // namespace
}  // namespace tlvlink::quantize
