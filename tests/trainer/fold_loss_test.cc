// BatchNorm folding (by hand and against an unfolded conv + BN computed directly) and the
// symmetric InfoNCE loss on hand-checkable cases.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tlvlink/trainer/fold.h"
#include "tlvlink/trainer/trainer.h"

namespace tlvlink::trainer {
namespace {

TEST(Fold, HandCase) {
  // 1x1 conv, one channel: w = 2; BN gamma 3, beta 1, mean 0.5, var 3, eps 1 -> s = 3/2.
  const std::vector<float> w = {2.0f};
  BatchNormParams bn{{3.0f}, {1.0f}, {0.5f}, {3.0f}, 1.0f};
  auto f = fold_batchnorm(w, {1, 1, 1, 1}, {}, bn);
  ASSERT_TRUE(f.ok());
  EXPECT_FLOAT_EQ(f->weight_ohwi[0], 3.0f);  // 1.5 * 2
  EXPECT_FLOAT_EQ(f->bias[0], 0.25f);        // 1.5 * (0 - 0.5) + 1
  auto with_bias = fold_batchnorm(w, {1, 1, 1, 1}, std::vector<float>{0.5f}, bn);
  EXPECT_FLOAT_EQ(with_bias->bias[0], 1.0f);  // 1.5 * (0.5 - 0.5) + 1
}

// conv (OIHW weights, NHWC input, stride 1, padding 1) on one image, plain loops.
std::vector<double> conv_nhwc(const std::vector<float>& x, int h, int w, int cin,
                              const std::vector<float>& weight, bool ohwi, int cout, int k,
                              const std::vector<float>& bias) {
  std::vector<double> y(static_cast<size_t>(h * w * cout));
  for (int oy = 0; oy < h; ++oy)
    for (int ox = 0; ox < w; ++ox)
      for (int o = 0; o < cout; ++o) {
        double acc = bias.empty() ? 0.0 : static_cast<double>(bias[static_cast<size_t>(o)]);
        for (int ky = 0; ky < k; ++ky)
          for (int kx = 0; kx < k; ++kx) {
            const int iy = oy + ky - k / 2, ix = ox + kx - k / 2;
            if (iy < 0 || iy >= h || ix < 0 || ix >= w) continue;
            for (int i = 0; i < cin; ++i) {
              const size_t wi = ohwi ? static_cast<size_t>(((o * k + ky) * k + kx) * cin + i)
                                     : static_cast<size_t>(((o * cin + i) * k + ky) * k + kx);
              acc += static_cast<double>(weight[wi]) *
                     static_cast<double>(x[static_cast<size_t>((iy * w + ix) * cin + i)]);
            }
          }
        y[static_cast<size_t>((oy * w + ox) * cout + o)] = acc;
      }
  return y;
}

TEST(Fold, MatchesConvThenBatchNorm) {
  const uint64_t seed = 1234;
  std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  std::uniform_real_distribution<float> positive(0.05f, 2.0f);
  const int h = 5, w = 6, cin = 4, cout = 7, k = 3;
  std::vector<float> x(static_cast<size_t>(h * w * cin)),
      weight(static_cast<size_t>(cout * cin * k * k));
  for (float& v : x) v = normal(rng);
  for (float& v : weight) v = 0.3f * normal(rng);
  BatchNormParams bn;
  bn.eps = 1e-5f;
  for (int c = 0; c < cout; ++c) {
    bn.gamma.push_back(normal(rng));
    bn.beta.push_back(normal(rng));
    bn.running_mean.push_back(normal(rng));
    bn.running_var.push_back(positive(rng));
  }
  const std::vector<double> raw = conv_nhwc(x, h, w, cin, weight, false, cout, k, {});
  auto folded = fold_batchnorm(weight, {cout, cin, k, k}, {}, bn);
  ASSERT_TRUE(folded.ok());
  const std::vector<double> got =
      conv_nhwc(x, h, w, cin, folded->weight_ohwi, true, cout, k, folded->bias);
  // Folded weights are rounded to float once: relative error ~ 2^-24 per weight, times the
  // conv's 36-term sum of O(1) values -> well below 1e-5.
  constexpr double kFoldTolerance = 1e-5;
  for (size_t i = 0; i < raw.size(); ++i) {
    const auto c = static_cast<size_t>(static_cast<int>(i) % cout);
    const double want =
        static_cast<double>(bn.gamma[c]) * (raw[i] - static_cast<double>(bn.running_mean[c])) /
            std::sqrt(static_cast<double>(bn.running_var[c]) + static_cast<double>(bn.eps)) +
        static_cast<double>(bn.beta[c]);
    EXPECT_NEAR(got[i], want, kFoldTolerance) << "output " << i;
  }
}

TEST(Fold, RejectsBadParameters) {
  const std::vector<float> w(8, 1.0f);
  BatchNormParams bn{{1, 1}, {0, 0}, {0, 0}, {1, -1}, 1e-5f};
  auto r = fold_batchnorm(w, {2, 1, 2, 2}, {}, bn);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(std::string(r.error().message()).find("negative running variance"), std::string::npos);
  bn.running_var = {1, 1};
  EXPECT_FALSE(fold_batchnorm(w, {2, 2, 2, 2}, {}, bn).ok());  // 8 weights, shape needs 16
  bn.running_var = {0, 1};
  bn.eps = 0;
  EXPECT_FALSE(fold_batchnorm(w, {2, 1, 2, 2}, {}, bn).ok());  // 1 / sqrt(0)
}

TEST(InfoNce, IdentityPairs) {
  // x = y = I (2x2), scale s: logits = s I; each CE = log(1 + e^-s).
  const std::vector<float> eye = {1, 0, 0, 1};
  for (double s : {1.0, 10.0}) {
    auto l = info_nce_loss(eye, eye, 2, 2, s);
    ASSERT_TRUE(l.ok());
    EXPECT_NEAR(*l, std::log1p(std::exp(-s)), 1e-6);
  }
}

TEST(InfoNce, HandCheckedAsymmetricCase) {
  // x = I, y = [[1,1],[1,-1]] (normalised inside): logits = s/sqrt2 [[1,1],[1,-1]] (symmetric).
  // Row 0: log 2. Row 1 (target 1): log(1 + e^{2a}), a = s/sqrt2. Both directions agree.
  const std::vector<float> x = {1, 0, 0, 1}, y = {1, 1, 1, -1};
  const double s = 1.0, a = s / std::sqrt(2.0);
  const double want = 0.5 * (std::log(2.0) + std::log1p(std::exp(2 * a)));  // = 1.162491...
  auto l = info_nce_loss(x, y, 2, 2, s);
  ASSERT_TRUE(l.ok());
  EXPECT_NEAR(*l, want, 1e-6);
  EXPECT_NEAR(*l, 1.162491, 1e-5);
  // Scaling the rows does not change the loss (both sides are L2-normalised).
  const std::vector<float> x3 = {3, 0, 0, 3};
  EXPECT_NEAR(info_nce_loss(x3, y, 2, 2, s).value(), want, 1e-6);
  EXPECT_FALSE(info_nce_loss(x, y, 3, 2, s).ok());  // sizes do not match [3, 2]
}

}  // namespace
}  // namespace tlvlink::trainer
