#pragma once
#ifndef TLVLINK_EVAL_PRIVATE
#error "logistic_internal.h is internal to tools/eval: include its public headers instead"
#endif
// Multinomial logistic regression on standardised features, by full-batch L-BFGS (double,
// fixed summation order, so the same data gives the same bits).

#include <cstdint>
#include <span>
#include <vector>

#include "tlvlink/eval/probe.h"

namespace tlvlink::eval::internal {

// Standardised training matrix: z[i * dim + j] = (x[i][j] - mean[j]) / std[j].
struct StdMatrix {
  std::vector<double> z;
  int64_t rows = 0;
  int32_t dim = 0;
  // Mean outer product of the standardised differences between view pairs ([dim, dim]; empty
  // when no pair): the view penalty is view_weight/2 * sum_k w_k^T view_cov w_k.
  std::vector<double> view_cov;
};
StdMatrix standardise(std::span<const float> x, int32_t dim, std::span<const int64_t> rows,
                      const Standardisation& s);
// Fills m.view_cov from `pairs` (rows of x, both among the rows m was standardised from).
void add_view_covariance(std::span<const float> x, std::span<const std::array<int64_t, 2>> pairs,
                         const Standardisation& s, StdMatrix& m);
Standardisation standardisation_of_rows(std::span<const float> x, int32_t dim,
                                        std::span<const int64_t> rows);

// Minimises mean cross-entropy + l2/2 |W|^2 (+ the view penalty) over theta = [W (classes x dim), b
// (classes)], starting from `theta` (warm start; zeros for a cold one).
struct Minimised {
  int32_t iterations = 0;
  bool converged = false;   // max |gradient| <= tolerance, or no further decrease possible
  double max_gradient = 0;  // at the returned theta
};
Minimised minimise_logistic(const StdMatrix& m, std::span<const int32_t> labels, int32_t classes,
                            const LogisticOptions& options, std::vector<double>& theta);

}  // namespace tlvlink::eval::internal
