#pragma once
// Linear probes: multinomial logistic regression with an L2 penalty, fitted by full-batch
// L-BFGS in double precision (deterministic: no randomness, fixed summation order). Features are
// standardised internally (z = (x - mean) / std over the training rows) and the standardisation
// is folded back, so the returned head acts on the RAW embedding exactly as the runtime applies
// a LinearHead: logits = W x + b.
//
//   ProbeData d{x, dim, labels, classes, groups};
//   auto probe = fit_probe(d, {});          // picks the L2 strength on a validation split by group
//   // probe->weight [classes, dim], probe->bias [classes]

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::eval {

// Training rows: x is [n, dim] row-major; labels in [0, classes) (rows with label -1 must be
// filtered out by the caller); groups (session/object) of each row, for the validation split.
struct ProbeData {
  std::span<const float> x;
  int32_t dim = 0;
  std::span<const int32_t> labels;
  int32_t classes = 0;
  std::span<const std::string> groups;  // may be empty: then no validation split is possible
  // Pairs of rows that are two views of one touch (a frame and its JPEG re-encoding; same
  // group, same label): with LogisticOptions::view_weight > 0 the fit penalises the head's
  // logit change between them. May be empty.
  std::span<const std::array<int64_t, 2>> view_pairs;
};

struct LogisticOptions {
  double l2 = 1e-3;                  // penalty l2/2 * |W|^2 on standardised weights (bias free)
  int32_t max_iterations = 300;      // L-BFGS iterations
  double gradient_tolerance = 1e-5;  // stop when max |gradient| falls below
  int32_t history = 10;              // L-BFGS memory
  // Penalty view_weight/2 * mean over view pairs of |W (z_a - z_b)|^2 (standardised features):
  // the head is steered away from the directions in which a codec moves the embedding, so its
  // answer changes less between two views of one touch. 0 = off. (fit_probe sets it from
  // ProbeOptions::view_weight_grid.)
  double view_weight = 0;
};

// L2 strength used when no validation split can be made (fewer than 2 groups).
inline constexpr double kFallbackL2 = 1e-2;

struct ProbeOptions {
  LogisticOptions logistic;
  // Candidate L2 strengths; the one with the best validation accuracy wins (ties: the larger,
  // i.e. the simpler model). One candidate: no validation split is made.
  std::vector<double> l2_grid = {1e-4, 1e-3, 1e-2, 1e-1, 1.0, 10.0};
  // Validation groups: the distinct groups ranked by datasets::split_hash_unit(group, seed), the
  // first max(1, round(n_groups * fraction)) of them, at most n_groups - 1 (needs >= 2 groups;
  // otherwise kFallbackL2 is used and FittedProbe::note says so).
  double validation_fraction = 0.2;
  uint64_t validation_seed = 0;
  // View-penalty strengths tried (LogisticOptions::view_weight; needs ProbeData::view_pairs),
  // each with its best L2. With min_view_agreement 0 the most accurate wins on validation (ties:
  // the smaller weight); otherwise the smallest weight whose fit gives both views of a
  // validation touch the same answer on >= min_view_agreement of the pairs (none: the most
  // agreeing). One entry {0}: the plain fit. Without pairs the grid is ignored; without a
  // validation split the smallest weight is used.
  std::vector<double> view_weight_grid = {0.0};
  double min_view_agreement = 0;
};

// One view weight's validation result (FittedProbe::view_trials).
struct ViewWeightTrial {
  double view_weight = 0, l2 = 0;
  double accuracy = 0;   // validation accuracy at that l2
  double agreement = 0;  // share of validation view pairs given the same answer
};

// A fitted probe in raw-embedding form plus how it was chosen.
struct FittedProbe {
  std::vector<float> weight;  // [classes, dim]
  std::vector<float> bias;    // [classes]
  int32_t classes = 0, dim = 0;
  double l2 = 0;                             // chosen strength
  double view_weight = 0;                    // chosen view-penalty strength
  std::vector<double> validation_accuracy;   // per l2_grid entry at the chosen view weight
                                             // ([] when no validation split)
  std::vector<ViewWeightTrial> view_trials;  // per view_weight_grid entry ([] without pairs)
  int64_t train_rows = 0, validation_rows = 0;
  int64_t train_groups = 0, validation_groups = 0;
  double train_accuracy = 0;  // final fit (all training rows), raw-form head
  int32_t iterations = 0;     // of the final fit
  bool converged = true;      // final fit met the tolerance (else `note` says so)
  std::string note;           // e.g. "no validation split: 1 group"
};

// Errors: empty data, shape mismatch, label outside [0, classes), non-finite features, bad
// options (empty grid, l2 < 0, fraction outside (0, 1)).
Result<FittedProbe> fit_probe(const ProbeData& data, const ProbeOptions& options);

// One fit at a fixed L2 (no validation); the building block of fit_probe.
Result<FittedProbe> fit_logistic(const ProbeData& data, const LogisticOptions& options);

// Standardisation folded into a head acting on standardised features z = (x - mean) / std:
// W' = W / std (per column), b' = b - W' mean. Computed in double. Exposed for tests.
struct Standardisation {
  std::vector<double> mean, std;  // std of a constant column is 1 (it then contributes nothing)
};
Standardisation standardisation_of(std::span<const float> x, int32_t dim);
void fold_standardisation(const Standardisation& s, std::span<const double> w_std,
                          std::span<const double> b_std, int32_t classes,
                          std::vector<float>& weight, std::vector<float>& bias);

// Logits and argmax are the runtime's: heads::linear_logits, heads::argmax
// (tlvlink/heads/head_math.h).

}  // namespace tlvlink::eval
