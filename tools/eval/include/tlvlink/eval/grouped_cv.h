#pragma once
// Grouped cross-validation of a linear head (multinomial logistic regression, probe.h) on
// labelled rows that come in groups (objects, sessions): a group's rows are never split between
// fitting and scoring, folds are stratified (each fold gets its share of every class's groups),
// and the L2 strength is chosen by a grouped cross-validation inside each fitting fold, so no
// scored row ever influences its own model. Deterministic: groups are ordered by
// datasets::split_hash_unit(group, seed), the bootstrap uses a seeded generator.
//
//   GroupedRows rows{x, dim, labels, classes, groups};
//   auto cv = cross_validate(rows, {});
//   // cv->accuracy, cv->ci_low..ci_high (95 %, bootstrap over groups), cv->balanced_accuracy

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/eval/probe.h"

namespace tlvlink::eval {

struct GroupedRows {
  std::span<const float> x;  // [n, dim]
  int32_t dim = 0;
  std::span<const int32_t> labels;  // in [0, classes)
  int32_t classes = 0;
  std::span<const std::string> groups;            // one per row
  std::span<const std::string> class_names = {};  // optional, for messages
};

struct CvOptions {
  int32_t folds = 5;  // at most; fewer when a class has fewer groups (at least 2 needed)
  std::vector<double> l2_grid = {1e-3, 1e-2, 1e-1, 1.0, 10.0, 100.0};
  LogisticOptions logistic;
  uint64_t seed = 0;
  int32_t bootstrap = 2000;  // resamples of the groups for the 95 % interval
};

struct CvResult {
  int32_t folds = 0;
  int64_t n = 0, groups = 0;
  double accuracy = 0, ci_low = 0, ci_high = 0;
  double balanced_accuracy = 0;  // mean per-class recall
  double majority = 0;           // share of the commonest class
  std::vector<int64_t> class_rows, class_groups;
  std::vector<int32_t> predicted;  // per row, by the fold's model that did not see it
  std::vector<int32_t> fold;       // per row, the fold that scored it (its groups' fold)
  std::vector<double> fold_l2;     // the strength chosen inside each fitting fold
};

// Errors: bad shapes, labels outside [0, classes), non-finite features, fewer than two classes
// present, or a class with fewer than two groups (no fold could score it on an unseen group):
// the message names the class and its groups.
Result<CvResult> cross_validate(const GroupedRows& rows, const CvOptions& options);

// The L2 strength a grouped cross-validation over `rows` prefers (ties: the larger). When a
// class has fewer than two groups there is nothing to validate on: kFallbackL2.
Result<double> choose_l2(const GroupedRows& rows, const CvOptions& options);

// The head fitted on every row with choose_l2's strength, in raw form (probe.h FittedProbe).
Result<FittedProbe> fit_grouped(const GroupedRows& rows, const CvOptions& options);

// Accuracy, balanced accuracy (mean per-class recall over the classes present) and the majority
// rate of answers scored against labels in [0, classes): the figures every head report states.
struct ClassMetrics {
  double accuracy = 0, balanced_accuracy = 0, majority = 0;
  std::vector<int64_t> class_rows;  // rows per class
};
ClassMetrics class_metrics(std::span<const int32_t> labels, std::span<const uint8_t> correct,
                           int32_t classes);

// 95 % interval of an accuracy whose rows come in groups: the groups resampled with replacement
// (`resamples` times, seeded), the 2.5 and 97.5 percentiles, widened to hold Wilson's score
// interval at the effective sample size (n / the design effect the groups' resampling shows), so
// a perfect score on few groups is not a point. Frames of one object are not independent, so
// resampling frames would be too narrow.
struct Interval {
  double low = 0, high = 0;
};
Interval group_bootstrap_interval(std::span<const uint8_t> correct,
                                  std::span<const std::string> groups, uint64_t seed,
                                  int32_t resamples = 2000);

// How accuracy grows with the number of labelled groups: for k groups per class, every choice
// of k groups of each class (or `draws` seeded random choices when there are more) is fitted
// and scored on all the other groups.
struct CurvePoint {
  int32_t groups_per_class = 0;
  int32_t draws = 0;
  double mean = 0, min = 0, max = 0;  // accuracy over the draws
  double mean_test_rows = 0;
};
// k runs from 1 to (fewest groups of a class) - 1. Same errors as cross_validate.
Result<std::vector<CurvePoint>> learning_curve(const GroupedRows& rows, const CvOptions& options,
                                               int32_t draws = 30);

}  // namespace tlvlink::eval
