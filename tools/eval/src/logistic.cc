// Standardisation, its folding into a raw-embedding head, and the L-BFGS logistic fit.

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "logistic_internal.h"

namespace tlvlink::eval {
namespace internal {
namespace {

// A column whose spread is below this (relative to its magnitude) is treated as constant: it
// is centred but not scaled, so it contributes nothing and cannot blow up the folded weights.
constexpr double kConstantColumnRelStd = 1e-9;
// Armijo sufficient-decrease constant and the smallest step tried before giving up a line search.
constexpr double kArmijo = 1e-4;
constexpr double kMinStep = 1e-12;
// A step that lowers the objective by less than this (relative) ends the fit: the accuracy of a
// probe cannot change at that level.
constexpr double kStallDecrease = 1e-12;

// Dot product with four independent partial sums (a fixed order, so still deterministic): breaks
// the add-latency chain of a single accumulator, ~3x faster on long rows.
double dot4(const double* a, const double* b, size_t n) {
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  size_t j = 0;
  for (; j + 4 <= n; j += 4) {
    s0 += a[j] * b[j];
    s1 += a[j + 1] * b[j + 1];
    s2 += a[j + 2] * b[j + 2];
    s3 += a[j + 3] * b[j + 3];
  }
  for (; j < n; ++j) s0 += a[j] * b[j];
  return (s0 + s1) + (s2 + s3);
}

// view_weight/2 * sum_k w_k^T C w_k, its gradient added into `grad` (C symmetric).
double view_penalty(const StdMatrix& m, size_t classes, double view_weight,
                    std::span<const double> theta, std::vector<double>& grad) {
  if (view_weight <= 0 || m.view_cov.empty()) return 0;
  const auto d = static_cast<size_t>(m.dim);
  std::vector<double> cw(d);
  double penalty = 0;
  for (size_t k = 0; k < classes; ++k) {
    const double* w = theta.data() + k * d;
    for (size_t i = 0; i < d; ++i) cw[i] = dot4(m.view_cov.data() + i * d, w, d);
    penalty += dot4(w, cw.data(), d);
    for (size_t i = 0; i < d; ++i) grad[k * d + i] += view_weight * cw[i];
  }
  return 0.5 * view_weight * penalty;
}

// f(theta) and its gradient: mean cross-entropy + l2/2 |W|^2 + the view penalty.
double objective(const StdMatrix& m, std::span<const int32_t> labels, int32_t classes,
                 const LogisticOptions& o, std::span<const double> theta,
                 std::vector<double>& grad) {
  const double l2 = o.l2;
  const auto d = static_cast<size_t>(m.dim);
  const auto c = static_cast<size_t>(classes);
  const double* w = theta.data();
  const double* b = theta.data() + c * d;
  std::fill(grad.begin(), grad.end(), 0.0);
  double* gw = grad.data();
  double* gb = grad.data() + c * d;
  std::vector<double> logits(c), probs(c);
  double loss = 0;
  for (int64_t i = 0; i < m.rows; ++i) {
    const double* z = m.z.data() + static_cast<size_t>(i) * d;
    double top = -std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < c; ++k) {
      logits[k] = b[k] + dot4(w + k * d, z, d);
      top = std::max(top, logits[k]);
    }
    double sum = 0;
    for (size_t k = 0; k < c; ++k) {
      probs[k] = std::exp(logits[k] - top);
      sum += probs[k];
    }
    const auto y = static_cast<size_t>(labels[static_cast<size_t>(i)]);
    loss += top + std::log(sum) - logits[y];
    const double inv_sum = 1.0 / sum;
    for (size_t k = 0; k < c; ++k) {
      const double r = probs[k] * inv_sum - (k == y ? 1.0 : 0.0);
      gb[k] += r;
      double* gk = gw + k * d;
      for (size_t j = 0; j < d; ++j) gk[j] += r * z[j];
    }
  }
  const double inv_n = 1.0 / static_cast<double>(m.rows);
  double penalty = 0;
  for (size_t k = 0; k < c * d; ++k) {
    grad[k] = grad[k] * inv_n + l2 * theta[k];
    penalty += theta[k] * theta[k];
  }
  for (size_t k = c * d; k < grad.size(); ++k) grad[k] *= inv_n;
  return loss * inv_n + 0.5 * l2 * penalty + view_penalty(m, c, o.view_weight, theta, grad);
}

double dot(std::span<const double> a, std::span<const double> b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

double max_abs(std::span<const double> v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

}  // namespace

Standardisation standardisation_of_rows(std::span<const float> x, int32_t dim,
                                        std::span<const int64_t> rows) {
  const auto d = static_cast<size_t>(dim);
  Standardisation s;
  s.mean.assign(d, 0.0);
  s.std.assign(d, 0.0);
  for (int64_t r : rows)
    for (size_t j = 0; j < d; ++j)
      s.mean[j] += static_cast<double>(x[static_cast<size_t>(r) * d + j]);
  const double n = static_cast<double>(std::max<size_t>(rows.size(), 1));
  for (double& v : s.mean) v /= n;
  for (int64_t r : rows) {
    for (size_t j = 0; j < d; ++j) {
      const double dv = static_cast<double>(x[static_cast<size_t>(r) * d + j]) - s.mean[j];
      s.std[j] += dv * dv;
    }
  }
  for (size_t j = 0; j < d; ++j) {
    const double sd = std::sqrt(s.std[j] / n);
    s.std[j] = sd > kConstantColumnRelStd * (1.0 + std::fabs(s.mean[j])) ? sd : 1.0;
  }
  return s;
}

StdMatrix standardise(std::span<const float> x, int32_t dim, std::span<const int64_t> rows,
                      const Standardisation& s) {
  const auto d = static_cast<size_t>(dim);
  StdMatrix m;
  m.rows = static_cast<int64_t>(rows.size());
  m.dim = dim;
  m.z.resize(rows.size() * d);
  for (size_t i = 0; i < rows.size(); ++i) {
    const float* src = x.data() + static_cast<size_t>(rows[i]) * d;
    for (size_t j = 0; j < d; ++j)
      m.z[i * d + j] = (static_cast<double>(src[j]) - s.mean[j]) / s.std[j];
  }
  return m;
}

void add_view_covariance(std::span<const float> x, std::span<const std::array<int64_t, 2>> pairs,
                         const Standardisation& s, StdMatrix& m) {
  m.view_cov.clear();
  if (pairs.empty()) return;
  const auto d = static_cast<size_t>(m.dim);
  std::vector<double> cov(d * d, 0.0), delta(d);
  for (const auto& [a, b] : pairs) {
    const float* xa = x.data() + static_cast<size_t>(a) * d;
    const float* xb = x.data() + static_cast<size_t>(b) * d;
    for (size_t j = 0; j < d; ++j)
      delta[j] = (static_cast<double>(xa[j]) - static_cast<double>(xb[j])) / s.std[j];
    for (size_t i = 0; i < d; ++i)
      for (size_t j = 0; j <= i; ++j) cov[i * d + j] += delta[i] * delta[j];
  }
  const auto n = static_cast<double>(pairs.size());
  for (size_t i = 0; i < d; ++i) {
    for (size_t j = 0; j <= i; ++j) {
      cov[i * d + j] /= n;
      cov[j * d + i] = cov[i * d + j];
    }
  }
  m.view_cov = std::move(cov);
}

Minimised minimise_logistic(const StdMatrix& m, std::span<const int32_t> labels, int32_t classes,
                            const LogisticOptions& o, std::vector<double>& theta) {
  const size_t p = static_cast<size_t>(classes) * (static_cast<size_t>(m.dim) + 1);
  theta.resize(p, 0.0);
  std::vector<double> g(p), g_new(p), dir(p), x_new(p), alpha(static_cast<size_t>(o.history));
  std::deque<std::vector<double>> s_hist, y_hist;
  std::deque<double> rho_hist;
  double f = objective(m, labels, classes, o, theta, g);
  int32_t it = 0;
  bool stalled = false;
  for (; it < o.max_iterations && max_abs(g) > o.gradient_tolerance; ++it) {
    // Two-loop recursion: dir = -H g.
    for (size_t i = 0; i < p; ++i) dir[i] = -g[i];
    const size_t h = s_hist.size();
    for (size_t k = h; k-- > 0;) {
      alpha[k] = rho_hist[k] * dot(s_hist[k], dir);
      for (size_t i = 0; i < p; ++i) dir[i] -= alpha[k] * y_hist[k][i];
    }
    double gamma = 1.0;
    if (h > 0)
      gamma = dot(s_hist[h - 1], y_hist[h - 1]) / dot(y_hist[h - 1], y_hist[h - 1]);
    else
      gamma = 1.0 / std::max(1.0, std::sqrt(dot(g, g)));
    for (double& v : dir) v *= gamma;
    for (size_t k = 0; k < h; ++k) {
      const double beta = rho_hist[k] * dot(y_hist[k], dir);
      for (size_t i = 0; i < p; ++i) dir[i] += s_hist[k][i] * (alpha[k] - beta);
    }
    double slope = dot(g, dir);
    if (slope >= 0) {  // not a descent direction (numerical trouble): restart from steepest descent
      s_hist.clear(), y_hist.clear(), rho_hist.clear();
      for (size_t i = 0; i < p; ++i) dir[i] = -g[i] / std::max(1.0, std::sqrt(dot(g, g)));
      slope = dot(g, dir);
    }
    double step = 1.0, f_new = f;
    bool accepted = false;
    for (; step >= kMinStep; step *= 0.5) {
      for (size_t i = 0; i < p; ++i) x_new[i] = theta[i] + step * dir[i];
      f_new = objective(m, labels, classes, o, x_new, g_new);
      if (f_new <= f + kArmijo * step * slope) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {  // no decrease possible at double precision: as good as it gets
      stalled = true;
      break;
    }
    std::vector<double> s(p), y(p);
    for (size_t i = 0; i < p; ++i) {
      s[i] = x_new[i] - theta[i];
      y[i] = g_new[i] - g[i];
    }
    const double sy = dot(s, y);
    if (sy > 1e-12 * std::sqrt(dot(s, s) * dot(y, y))) {
      if (s_hist.size() == static_cast<size_t>(o.history)) {
        s_hist.pop_front(), y_hist.pop_front(), rho_hist.pop_front();
      }
      s_hist.push_back(std::move(s));
      y_hist.push_back(std::move(y));
      rho_hist.push_back(1.0 / sy);
    }
    theta.swap(x_new);
    g.swap(g_new);
    const double decrease = f - f_new;
    f = f_new;
    if (decrease <= kStallDecrease * std::max(1.0, std::fabs(f))) {
      ++it;
      stalled = true;
      break;
    }
  }
  const double gmax = max_abs(g);
  return {it, stalled || gmax <= o.gradient_tolerance, gmax};
}

}  // namespace internal

Standardisation standardisation_of(std::span<const float> x, int32_t dim) {
  std::vector<int64_t> rows(x.size() / static_cast<size_t>(dim));
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<int64_t>(i);
  return internal::standardisation_of_rows(x, dim, rows);
}

void fold_standardisation(const Standardisation& s, std::span<const double> w_std,
                          std::span<const double> b_std, int32_t classes,
                          std::vector<float>& weight, std::vector<float>& bias) {
  const size_t d = s.mean.size();
  const auto c = static_cast<size_t>(classes);
  weight.resize(c * d);
  bias.resize(c);
  for (size_t k = 0; k < c; ++k) {
    double b = b_std[k];
    for (size_t j = 0; j < d; ++j) {
      const double w = w_std[k * d + j] / s.std[j];
      weight[k * d + j] = static_cast<float>(w);
      b -= w * s.mean[j];
    }
    bias[k] = static_cast<float>(b);
  }
}

}  // namespace tlvlink::eval
