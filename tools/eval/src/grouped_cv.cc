// Grouped, stratified cross-validation with the L2 strength chosen inside the fitting folds
// (grouped_cv.h).

#include "tlvlink/eval/grouped_cv.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>

#include "tlvlink/datasets/split.h"
#include "tlvlink/heads/head_math.h"

namespace tlvlink::eval {
namespace {

// Rows with their groups numbered, each group's class (its commonest label) and every class's
// groups in hash order.
struct Indexed {
  std::vector<int32_t> group_of_row;
  std::vector<std::string> group_names;
  std::vector<int32_t> group_class;
  std::vector<std::vector<int32_t>> class_groups;  // per class: groups whose commonest class it
                                                   // is, in split_hash_unit order (fold dealing)
  std::vector<std::vector<int32_t>> groups_with;   // per class: every group holding rows of it
};

Status validate(const GroupedRows& r) {
  const size_t n = r.labels.size();
  TLV_ENSURE(r.dim > 0 && r.classes >= 2 && n > 0, ErrorCode::kInvalidArgument,
             "cross-validation: %zu rows of dim %d in %d classes (need rows, dim > 0, classes "
             ">= 2)",
             n, r.dim, r.classes);
  TLV_ENSURE(r.x.size() == n * static_cast<size_t>(r.dim) && r.groups.size() == n,
             ErrorCode::kShapeMismatch,
             "cross-validation: %zu features and %zu groups for %zu rows "
             "of dim %d",
             r.x.size(), r.groups.size(), n, r.dim);
  for (size_t i = 0; i < n; ++i) {
    TLV_ENSURE(r.labels[i] >= 0 && r.labels[i] < r.classes, ErrorCode::kInvalidArgument,
               "cross-validation: row %zu has label %d outside [0, %d)", i, r.labels[i], r.classes);
  }
  for (size_t i = 0; i < r.x.size(); ++i) {
    TLV_ENSURE(std::isfinite(r.x[i]), ErrorCode::kNonFiniteValue,
               "cross-validation: feature %zu of row %zu is not finite",
               i % static_cast<size_t>(r.dim), i / static_cast<size_t>(r.dim));
  }
  return {};
}

Indexed index_rows(const GroupedRows& r, uint64_t seed) {
  Indexed ix;
  std::map<std::string, int32_t> ids;
  std::vector<std::vector<int64_t>> counts;
  for (size_t i = 0; i < r.labels.size(); ++i) {
    auto [it, added] = ids.emplace(r.groups[i], static_cast<int32_t>(ix.group_names.size()));
    if (added) {
      ix.group_names.push_back(r.groups[i]);
      counts.emplace_back(static_cast<size_t>(r.classes), 0);
    }
    ix.group_of_row.push_back(it->second);
    ++counts[static_cast<size_t>(it->second)][static_cast<size_t>(r.labels[i])];
  }
  ix.class_groups.resize(static_cast<size_t>(r.classes));
  ix.groups_with.resize(static_cast<size_t>(r.classes));
  for (size_t g = 0; g < counts.size(); ++g) {
    for (size_t c = 0; c < counts[g].size(); ++c)
      if (counts[g][c] > 0) ix.groups_with[c].push_back(static_cast<int32_t>(g));
    const auto c = static_cast<int32_t>(std::max_element(counts[g].begin(), counts[g].end()) -
                                        counts[g].begin());
    ix.group_class.push_back(c);
    ix.class_groups[static_cast<size_t>(c)].push_back(static_cast<int32_t>(g));
  }
  for (auto* lists : {&ix.class_groups, &ix.groups_with})
    for (auto& groups : *lists) {
      std::sort(groups.begin(), groups.end(), [&](int32_t a, int32_t b) {
        const double ha = datasets::split_hash_unit(ix.group_names[static_cast<size_t>(a)], seed);
        const double hb = datasets::split_hash_unit(ix.group_names[static_cast<size_t>(b)], seed);
        return ha != hb ? ha < hb
                        : ix.group_names[static_cast<size_t>(a)] <
                              ix.group_names[static_cast<size_t>(b)];
      });
    }
  return ix;
}

// Fewest groups holding rows of a class, over the classes that have rows (a group may hold
// several classes: one object seen slipping and not).
int32_t fewest_groups(const Indexed& ix) {
  int32_t fewest = INT32_MAX;
  for (const auto& g : ix.groups_with)
    if (!g.empty()) fewest = std::min(fewest, static_cast<int32_t>(g.size()));
  return fewest == INT32_MAX ? 0 : fewest;
}

int32_t classes_present(const Indexed& ix) {
  int32_t present = 0;
  for (const auto& g : ix.groups_with) present += g.empty() ? 0 : 1;
  return present;
}

// Stratified fold of every group: a class's groups dealt in hash order, each class starting one
// fold further on so folds come out alike in size.
std::vector<int32_t> fold_of_groups(const Indexed& ix, int32_t folds) {
  std::vector<int32_t> fold(ix.group_names.size(), 0);
  for (size_t c = 0; c < ix.class_groups.size(); ++c) {
    const auto& groups = ix.class_groups[c];
    for (size_t i = 0; i < groups.size(); ++i)
      fold[static_cast<size_t>(groups[i])] =
          static_cast<int32_t>((i + c) % static_cast<size_t>(folds));
  }
  return fold;
}

// An owned copy of some rows.
struct Subset {
  std::vector<float> x;
  std::vector<int32_t> labels;
  std::vector<std::string> groups;
  GroupedRows view(const GroupedRows& like) const {
    return {x, like.dim, labels, like.classes, groups, like.class_names};
  }
};
Subset subset(const GroupedRows& r, std::span<const int64_t> rows) {
  Subset s;
  const auto dim = static_cast<size_t>(r.dim);
  for (int64_t i : rows) {
    const auto u = static_cast<size_t>(i);
    s.x.insert(s.x.end(), r.x.begin() + static_cast<ptrdiff_t>(u * dim),
               r.x.begin() + static_cast<ptrdiff_t>((u + 1) * dim));
    s.labels.push_back(r.labels[u]);
    s.groups.push_back(r.groups[u]);
  }
  return s;
}

Result<FittedProbe> fit_at(const GroupedRows& r, const CvOptions& o, double l2) {
  LogisticOptions lo = o.logistic;
  lo.l2 = l2;
  return fit_logistic(ProbeData{r.x, r.dim, r.labels, r.classes, r.groups, {}}, lo);
}

int32_t predict(const FittedProbe& p, const GroupedRows& r, size_t row) {
  std::vector<float> logits(static_cast<size_t>(p.classes));
  const auto dim = static_cast<size_t>(r.dim);
  heads::linear_logits(p.weight, p.bias, r.x.subspan(row * dim, dim), logits);
  return heads::argmax(logits);
}

// Out-of-fold predictions of every row at a fixed strength (l2 < 0: chosen inside each fold).
Result<std::vector<int32_t>> out_of_fold(const GroupedRows& r, const CvOptions& o,
                                         const Indexed& ix, int32_t folds, double l2,
                                         std::vector<double>* chosen) {
  const std::vector<int32_t> fold = fold_of_groups(ix, folds);
  std::vector<int32_t> predicted(r.labels.size(), -1);
  for (int32_t f = 0; f < folds; ++f) {
    std::vector<int64_t> fit_rows, score_rows;
    for (size_t i = 0; i < r.labels.size(); ++i) {
      const bool scored = fold[static_cast<size_t>(ix.group_of_row[i])] == f;
      (scored ? score_rows : fit_rows).push_back(static_cast<int64_t>(i));
    }
    if (score_rows.empty()) continue;
    const Subset s = subset(r, fit_rows);
    const GroupedRows fit_view = s.view(r);
    double strength = l2;
    if (strength < 0) {
      TLV_ASSIGN_OR_RETURN(strength, choose_l2(fit_view, o));
      if (chosen != nullptr) chosen->push_back(strength);
    }
    TLV_ASSIGN_OR_RETURN(FittedProbe p, fit_at(fit_view, o, strength));
    for (int64_t i : score_rows)
      predicted[static_cast<size_t>(i)] = predict(p, r, static_cast<size_t>(i));
  }
  return predicted;
}

Status need_two_groups_per_class(const GroupedRows& r, const Indexed& ix) {
  TLV_ENSURE(classes_present(ix) >= 2, ErrorCode::kInvalidArgument,
             "cross-validation: the frames hold %d class(es); a head needs two",
             classes_present(ix));
  for (size_t c = 0; c < ix.groups_with.size(); ++c) {
    const auto& g = ix.groups_with[c];
    TLV_ENSURE(g.empty() || g.size() >= 2, ErrorCode::kInvalidArgument,
               "cross-validation: class '%s' has frames of one group only (%s); every class "
               "needs frames of at least two groups (objects or sessions) so a fold can score it "
               "on one it was not fitted on",
               c < r.class_names.size() ? r.class_names[c].c_str() : std::to_string(c).c_str(),
               ix.group_names[static_cast<size_t>(g[0])].c_str());
  }
  return {};
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

}  // namespace

Result<double> choose_l2(const GroupedRows& r, const CvOptions& o) {
  TLV_TRY(validate(r));
  TLV_ENSURE(!o.l2_grid.empty(), ErrorCode::kInvalidArgument, "cross-validation: empty L2 grid");
  const Indexed ix = index_rows(r, o.seed);
  const int32_t folds = std::min(o.folds, fewest_groups(ix));
  if (folds < 2 || classes_present(ix) < 2 || o.l2_grid.size() == 1)
    return o.l2_grid.size() == 1 ? o.l2_grid[0] : kFallbackL2;
  double best_l2 = o.l2_grid[0];
  int64_t best_correct = -1;
  for (double l2 : o.l2_grid) {
    TLV_ASSIGN_OR_RETURN(std::vector<int32_t> predicted, out_of_fold(r, o, ix, folds, l2, nullptr));
    int64_t correct = 0;
    for (size_t i = 0; i < predicted.size(); ++i) correct += predicted[i] == r.labels[i] ? 1 : 0;
    if (correct > best_correct || (correct == best_correct && l2 > best_l2)) {
      best_correct = correct;
      best_l2 = l2;
    }
  }
  return best_l2;
}

Result<FittedProbe> fit_grouped(const GroupedRows& r, const CvOptions& o) {
  TLV_ASSIGN_OR_RETURN(double l2, choose_l2(r, o));
  TLV_ASSIGN_OR_RETURN(FittedProbe p, fit_at(r, o, l2));
  p.l2 = l2;
  return p;
}

Result<CvResult> cross_validate(const GroupedRows& r, const CvOptions& o) {
  TLV_TRY(validate(r));
  TLV_ENSURE(o.folds >= 2 && o.bootstrap >= 100, ErrorCode::kInvalidArgument,
             "cross-validation: folds %d (>= 2) and bootstrap %d (>= 100)", o.folds, o.bootstrap);
  const Indexed ix = index_rows(r, o.seed);
  TLV_TRY(need_two_groups_per_class(r, ix));
  CvResult cv;
  cv.folds = std::min(o.folds, fewest_groups(ix));
  cv.n = static_cast<int64_t>(r.labels.size());
  cv.groups = static_cast<int64_t>(ix.group_names.size());
  auto predicted = out_of_fold(r, o, ix, cv.folds, -1, &cv.fold_l2);
  if (!predicted.ok()) return predicted.error();
  cv.predicted = std::move(predicted).value();
  const std::vector<int32_t> group_fold = fold_of_groups(ix, cv.folds);
  cv.fold.resize(cv.predicted.size());
  for (size_t i = 0; i < cv.fold.size(); ++i)
    cv.fold[i] = group_fold[static_cast<size_t>(ix.group_of_row[i])];

  std::vector<uint8_t> right(r.labels.size());
  for (size_t i = 0; i < right.size(); ++i) right[i] = cv.predicted[i] == r.labels[i] ? 1 : 0;
  ClassMetrics m = class_metrics(r.labels, right, r.classes);
  cv.accuracy = m.accuracy;
  cv.balanced_accuracy = m.balanced_accuracy;
  cv.majority = m.majority;
  cv.class_rows = std::move(m.class_rows);
  cv.class_groups.assign(static_cast<size_t>(r.classes), 0);
  for (size_t c = 0; c < cv.class_groups.size(); ++c)
    cv.class_groups[c] = static_cast<int64_t>(ix.groups_with[c].size());
  const Interval ci = group_bootstrap_interval(right, r.groups, o.seed, o.bootstrap);
  cv.ci_low = ci.low;
  cv.ci_high = ci.high;
  return cv;
}

ClassMetrics class_metrics(std::span<const int32_t> labels, std::span<const uint8_t> correct,
                           int32_t classes) {
  ClassMetrics m;
  m.class_rows.assign(static_cast<size_t>(classes), 0);
  std::vector<int64_t> class_correct(static_cast<size_t>(classes), 0);
  int64_t total = 0;
  for (size_t i = 0; i < labels.size(); ++i) {
    const auto c = static_cast<size_t>(labels[i]);
    ++m.class_rows[c];
    class_correct[c] += correct[i] ? 1 : 0;
    total += correct[i] ? 1 : 0;
  }
  if (labels.empty()) return m;
  const auto n = static_cast<double>(labels.size());
  m.accuracy = static_cast<double>(total) / n;
  m.majority = static_cast<double>(*std::max_element(m.class_rows.begin(), m.class_rows.end())) / n;
  double recall = 0;
  int32_t present = 0;
  for (size_t c = 0; c < m.class_rows.size(); ++c) {
    if (m.class_rows[c] == 0) continue;
    recall += static_cast<double>(class_correct[c]) / static_cast<double>(m.class_rows[c]);
    ++present;
  }
  m.balanced_accuracy = recall / present;
  return m;
}

Interval group_bootstrap_interval(std::span<const uint8_t> correct,
                                  std::span<const std::string> groups, uint64_t seed,
                                  int32_t resamples) {
  std::map<std::string, std::pair<int64_t, int64_t>> per_group;  // rows, correct
  int64_t total = 0;
  for (size_t i = 0; i < correct.size(); ++i) {
    auto& g = per_group[groups[i]];
    ++g.first;
    g.second += correct[i] ? 1 : 0;
    total += correct[i] ? 1 : 0;
  }
  if (correct.empty()) return {};
  const double accuracy = static_cast<double>(total) / static_cast<double>(correct.size());
  std::vector<std::pair<int64_t, int64_t>> g;
  for (const auto& [name, counts] : per_group) g.push_back(counts);
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ULL);
  std::uniform_int_distribution<size_t> pick(0, g.size() - 1);
  std::vector<double> resampled;
  resampled.reserve(static_cast<size_t>(std::max(resamples, 1)));
  for (int32_t b = 0; b < resamples; ++b) {
    int64_t rows = 0, right = 0;
    for (size_t k = 0; k < g.size(); ++k) {
      const auto& [n, c] = g[pick(rng)];
      rows += n;
      right += c;
    }
    resampled.push_back(static_cast<double>(right) / static_cast<double>(rows));
  }
  if (resampled.empty()) return {accuracy, accuracy};
  // With few groups the percentile interval collapses to a point when every group is all right
  // (or all wrong): "100 % [100, 100]" from 4 objects. So the interval also holds Wilson's score
  // interval at the effective sample size n / design effect, where the design effect is how much
  // the groups widen the binomial variance (>= 1; 1 when neither varies).
  double mean = 0, var = 0;
  for (double v : resampled) mean += v / static_cast<double>(resampled.size());
  for (double v : resampled) var += (v - mean) * (v - mean) / static_cast<double>(resampled.size());
  const auto n = static_cast<double>(correct.size());
  const double binomial = accuracy * (1 - accuracy) / n;
  const double design_effect = binomial > 0 ? std::max(1.0, var / binomial) : 1.0;
  const double n_eff = n / design_effect;
  constexpr double z = 1.959964;  // 95 %
  const double centre = (accuracy + z * z / (2 * n_eff)) / (1 + z * z / n_eff);
  const double half = z / (1 + z * z / n_eff) *
                      std::sqrt(accuracy * (1 - accuracy) / n_eff + z * z / (4 * n_eff * n_eff));
  return {std::min({accuracy, quantile(resampled, 0.025), centre - half}),
          std::max({accuracy, quantile(resampled, 0.975), centre + half})};
}

Result<std::vector<CurvePoint>> learning_curve(const GroupedRows& r, const CvOptions& o,
                                               int32_t draws) {
  TLV_TRY(validate(r));
  TLV_ENSURE(draws >= 1, ErrorCode::kInvalidArgument, "learning curve: draws %d (>= 1)", draws);
  const Indexed ix = index_rows(r, o.seed);
  TLV_TRY(need_two_groups_per_class(r, ix));
  std::vector<CurvePoint> curve;
  std::mt19937_64 rng(o.seed + 101);
  for (int32_t k = 1; k < fewest_groups(ix); ++k) {
    // Every combination when there are few (odometer over each class's k-subsets), else draws.
    std::vector<std::vector<std::vector<int32_t>>> per_class;  // class -> its k-subsets
    double combinations = 1;
    for (const auto& groups : ix.groups_with) {
      if (groups.empty()) continue;
      std::vector<std::vector<int32_t>> subsets;
      std::vector<bool> mask(groups.size(), false);
      std::fill(mask.begin(), mask.begin() + k, true);
      do {
        std::vector<int32_t> s;
        for (size_t i = 0; i < groups.size(); ++i)
          if (mask[i]) s.push_back(groups[i]);
        subsets.push_back(std::move(s));
      } while (std::prev_permutation(mask.begin(), mask.end()) && subsets.size() <= 4096);
      combinations *= static_cast<double>(subsets.size());
      per_class.push_back(std::move(subsets));
    }
    const bool all = combinations <= draws;
    const int32_t runs = all ? static_cast<int32_t>(combinations) : draws;
    CurvePoint point{k, runs, 0, 1, 0, 0};
    int32_t scored = 0;
    for (int32_t d = 0; d < runs; ++d) {
      std::vector<bool> chosen(ix.group_names.size(), false);
      int64_t code = d;
      for (const auto& subsets : per_class) {
        size_t pick_index;
        if (all) {
          pick_index = static_cast<size_t>(code % static_cast<int64_t>(subsets.size()));
          code /= static_cast<int64_t>(subsets.size());
        } else {
          pick_index = std::uniform_int_distribution<size_t>(0, subsets.size() - 1)(rng);
        }
        for (int32_t g : subsets[pick_index]) chosen[static_cast<size_t>(g)] = true;
      }
      std::vector<int64_t> fit_rows, score_rows;
      for (size_t i = 0; i < r.labels.size(); ++i)
        (chosen[static_cast<size_t>(ix.group_of_row[i])] ? fit_rows : score_rows)
            .push_back(static_cast<int64_t>(i));
      if (score_rows.empty()) continue;  // groups mixing classes: this draw took them all
      const Subset s = subset(r, fit_rows);
      TLV_ASSIGN_OR_RETURN(FittedProbe p, fit_grouped(s.view(r), o));
      int64_t right = 0;
      for (int64_t i : score_rows)
        right += predict(p, r, static_cast<size_t>(i)) == r.labels[static_cast<size_t>(i)] ? 1 : 0;
      const double acc = static_cast<double>(right) / static_cast<double>(score_rows.size());
      ++scored;
      point.mean += acc;
      point.min = std::min(point.min, acc);
      point.max = std::max(point.max, acc);
      point.mean_test_rows += static_cast<double>(score_rows.size());
    }
    if (scored == 0) break;
    point.draws = scored;
    point.mean /= scored;
    point.mean_test_rows /= scored;
    curve.push_back(point);
  }
  return curve;
}

}  // namespace tlvlink::eval
