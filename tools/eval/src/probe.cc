// fit_probe: L2 strength chosen on a validation split by group, then a final fit on all rows.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>

#include "logistic_internal.h"
#include "tlvlink/datasets/split.h"
#include "tlvlink/heads/head_math.h"

namespace tlvlink::eval {
namespace {

Status validate_data(const ProbeData& d) {
  TLV_ENSURE(d.dim > 0 && d.classes >= 2, ErrorCode::kInvalidArgument,
             "probe: dim %d and classes %d (need dim > 0, classes >= 2)", d.dim, d.classes);
  const size_t n = d.labels.size();
  TLV_ENSURE(n > 0, ErrorCode::kInvalidArgument, "probe: no training rows");
  TLV_ENSURE(d.x.size() == n * static_cast<size_t>(d.dim), ErrorCode::kShapeMismatch,
             "probe: %zu features for %zu rows of dim %d", d.x.size(), n, d.dim);
  TLV_ENSURE(d.groups.empty() || d.groups.size() == n, ErrorCode::kShapeMismatch,
             "probe: %zu groups for %zu rows", d.groups.size(), n);
  for (size_t i = 0; i < n; ++i) {
    TLV_ENSURE(d.labels[i] >= 0 && d.labels[i] < d.classes, ErrorCode::kInvalidArgument,
               "probe: row %zu has label %d outside [0, %d)", i, d.labels[i], d.classes);
  }
  for (const auto& [a, b] : d.view_pairs) {
    TLV_ENSURE(
        a >= 0 && b >= 0 && static_cast<size_t>(a) < n && static_cast<size_t>(b) < n && a != b,
        ErrorCode::kInvalidArgument,
        "probe: view pair (%lld, %lld): two distinct rows in [0, %zu) needed",
        static_cast<long long>(a), static_cast<long long>(b), n);
  }
  for (size_t i = 0; i < d.x.size(); ++i) {
    TLV_ENSURE(std::isfinite(d.x[i]), ErrorCode::kNonFiniteValue,
               "probe: feature %zu of row %zu is not finite", i % static_cast<size_t>(d.dim),
               i / static_cast<size_t>(d.dim));
  }
  return {};
}

Status validate_logistic(const LogisticOptions& o) {
  TLV_ENSURE(o.l2 >= 0 && std::isfinite(o.l2), ErrorCode::kInvalidArgument,
             "probe: l2 = %g must be finite and >= 0", o.l2);
  TLV_ENSURE(o.max_iterations >= 1 && o.history >= 1 && o.gradient_tolerance >= 0,
             ErrorCode::kInvalidArgument,
             "probe: max_iterations %d and history %d must be >= 1, tolerance >= 0",
             o.max_iterations, o.history);
  TLV_ENSURE(o.view_weight >= 0 && std::isfinite(o.view_weight), ErrorCode::kInvalidArgument,
             "probe: view weight %g must be finite and >= 0", o.view_weight);
  return {};
}

struct Fit {
  std::vector<float> weight, bias;
  std::vector<double> theta;  // standardised solution (warm start for the next fit)
  internal::Minimised result;
};

// The view pairs whose two rows are both among `rows` (sorted).
std::vector<std::array<int64_t, 2>> pairs_within(const ProbeData& d,
                                                 std::span<const int64_t> rows) {
  std::vector<std::array<int64_t, 2>> out;
  for (const auto& pair : d.view_pairs) {
    if (std::binary_search(rows.begin(), rows.end(), pair[0]) &&
        std::binary_search(rows.begin(), rows.end(), pair[1]))
      out.push_back(pair);
  }
  return out;
}

// Fits on `rows` (sorted) of the data, standardised over those rows; the head comes back folded.
Fit fit_rows(const ProbeData& d, std::span<const int64_t> rows, const LogisticOptions& o,
             std::vector<double> warm) {
  const Standardisation s = internal::standardisation_of_rows(d.x, d.dim, rows);
  internal::StdMatrix m = internal::standardise(d.x, d.dim, rows, s);
  if (o.view_weight > 0) internal::add_view_covariance(d.x, pairs_within(d, rows), s, m);
  std::vector<int32_t> labels(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) labels[i] = d.labels[static_cast<size_t>(rows[i])];
  Fit f;
  f.theta = std::move(warm);
  f.result = internal::minimise_logistic(m, labels, d.classes, o, f.theta);
  const size_t wd = static_cast<size_t>(d.classes) * static_cast<size_t>(d.dim);
  fold_standardisation(s, std::span<const double>(f.theta).first(wd),
                       std::span<const double>(f.theta).subspan(wd), d.classes, f.weight, f.bias);
  return f;
}

double accuracy(const ProbeData& d, const Fit& f, std::span<const int64_t> rows) {
  if (rows.empty()) return 0;
  std::vector<float> logits(static_cast<size_t>(d.classes));
  const auto dim = static_cast<size_t>(d.dim);
  int64_t correct = 0;
  for (int64_t r : rows) {
    heads::linear_logits(f.weight, f.bias, d.x.subspan(static_cast<size_t>(r) * dim, dim), logits);
    correct += heads::argmax(logits) == d.labels[static_cast<size_t>(r)] ? 1 : 0;
  }
  return static_cast<double>(correct) / static_cast<double>(rows.size());
}

// Share of `pairs` whose two rows get the same answer from the fit (1 when there are none).
double view_agreement(const ProbeData& d, const Fit& f,
                      std::span<const std::array<int64_t, 2>> pairs) {
  if (pairs.empty()) return 1;
  const auto dim = static_cast<size_t>(d.dim);
  std::vector<float> a(static_cast<size_t>(d.classes)), b(a.size());
  int64_t same = 0;
  for (const auto& [i, j] : pairs) {
    heads::linear_logits(f.weight, f.bias, d.x.subspan(static_cast<size_t>(i) * dim, dim), a);
    heads::linear_logits(f.weight, f.bias, d.x.subspan(static_cast<size_t>(j) * dim, dim), b);
    same += heads::argmax(a) == heads::argmax(b) ? 1 : 0;
  }
  return static_cast<double>(same) / static_cast<double>(pairs.size());
}

// ProbeOptions::min_view_agreement's rule over trials in ascending view weight.
size_t pick_view_weight(std::span<const ViewWeightTrial> trials, double min_agreement) {
  size_t best = 0;
  for (size_t i = 0; i < trials.size(); ++i) {
    if (min_agreement > 0) {
      if (trials[i].agreement >= min_agreement) return i;
      if (trials[i].agreement > trials[best].agreement) best = i;
    } else if (trials[i].accuracy > trials[best].accuracy) {
      best = i;
    }
  }
  return best;
}

void record_convergence(const Fit& f, const LogisticOptions& o, FittedProbe& p) {
  p.iterations = f.result.iterations;
  p.converged = f.result.converged;
  if (!p.converged) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "not converged in %d iterations (max |gradient| %.2g > %.2g)",
                  o.max_iterations, f.result.max_gradient, o.gradient_tolerance);
    p.note += (p.note.empty() ? "" : "; ") + std::string(buf);
  }
}

}  // namespace

Result<FittedProbe> fit_logistic(const ProbeData& d, const LogisticOptions& o) {
  TLV_TRY(validate_data(d));
  TLV_TRY(validate_logistic(o));
  std::vector<int64_t> rows(d.labels.size());
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<int64_t>(i);
  Fit f = fit_rows(d, rows, o, {});
  FittedProbe p;
  p.classes = d.classes;
  p.dim = d.dim;
  p.l2 = o.l2;
  p.train_rows = static_cast<int64_t>(rows.size());
  record_convergence(f, o, p);
  p.train_accuracy = accuracy(d, f, rows);
  p.weight = std::move(f.weight);
  p.bias = std::move(f.bias);
  return p;
}

Result<FittedProbe> fit_probe(const ProbeData& d, const ProbeOptions& options) {
  TLV_TRY(validate_data(d));
  TLV_TRY(validate_logistic(options.logistic));
  TLV_ENSURE(!options.l2_grid.empty(), ErrorCode::kInvalidArgument, "probe: empty l2 grid");
  for (double l2 : options.l2_grid) {
    TLV_ENSURE(l2 >= 0 && std::isfinite(l2), ErrorCode::kInvalidArgument,
               "probe: l2 grid value %g must be finite and >= 0", l2);
  }
  TLV_ENSURE(!options.view_weight_grid.empty(), ErrorCode::kInvalidArgument,
             "probe: empty view weight grid");
  for (double w : options.view_weight_grid) {
    TLV_ENSURE(w >= 0 && std::isfinite(w), ErrorCode::kInvalidArgument,
               "probe: view weight %g must be finite and >= 0", w);
  }
  TLV_ENSURE(options.min_view_agreement >= 0 && options.min_view_agreement <= 1,
             ErrorCode::kInvalidArgument, "probe: minimum view agreement %g outside [0, 1]",
             options.min_view_agreement);
  TLV_ENSURE(options.validation_fraction > 0 && options.validation_fraction < 1,
             ErrorCode::kInvalidArgument, "probe: validation fraction %g outside (0, 1)",
             options.validation_fraction);

  // Validation groups: lowest hash ranks, an exact count (deterministic, order-independent).
  std::map<std::string, std::vector<int64_t>> by_group;
  for (size_t i = 0; i < d.labels.size(); ++i)
    by_group[d.groups.empty() ? std::string() : d.groups[i]].push_back(static_cast<int64_t>(i));
  std::vector<std::pair<double, std::string>> ranked;
  for (const auto& [g, rows] : by_group)
    ranked.emplace_back(datasets::split_hash_unit(g, options.validation_seed), g);
  std::sort(ranked.begin(), ranked.end());
  const size_t n_groups = ranked.size();
  const size_t n_val =
      std::min(n_groups > 0 ? n_groups - 1 : 0,
               std::max<size_t>(1, static_cast<size_t>(std::lround(static_cast<double>(n_groups) *
                                                                   options.validation_fraction))));
  std::vector<int64_t> fit_part, val_rows, all_rows;
  for (size_t k = 0; k < n_groups; ++k) {
    const std::vector<int64_t>& rows = by_group[ranked[k].second];
    (k < n_val ? val_rows : fit_part)
        .insert((k < n_val ? val_rows : fit_part).end(), rows.begin(), rows.end());
  }
  for (size_t i = 0; i < d.labels.size(); ++i) all_rows.push_back(static_cast<int64_t>(i));
  std::sort(fit_part.begin(), fit_part.end());
  std::sort(val_rows.begin(), val_rows.end());

  FittedProbe p;
  p.classes = d.classes;
  p.dim = d.dim;
  p.train_rows = static_cast<int64_t>(all_rows.size());
  p.train_groups = static_cast<int64_t>(n_groups);
  LogisticOptions lo = options.logistic;
  std::vector<double> view_grid = {0.0};
  if (!d.view_pairs.empty()) {
    view_grid = options.view_weight_grid;
    std::sort(view_grid.begin(), view_grid.end());
  }
  std::vector<double> best_theta;
  const bool can_validate =
      (options.l2_grid.size() > 1 || view_grid.size() > 1) && n_groups >= 2 && n_val > 0;
  if (can_validate) {
    p.validation_rows = static_cast<int64_t>(val_rows.size());
    p.validation_groups = static_cast<int64_t>(n_val);
    const std::vector<std::array<int64_t, 2>> val_pairs = pairs_within(d, val_rows);
    // Strongest L2 first: each fit warm-starts the next (same optimum, fewer iterations).
    std::vector<size_t> order(options.l2_grid.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return options.l2_grid[a] > options.l2_grid[b]; });
    std::vector<std::vector<double>> accuracies, thetas;  // per view weight
    std::vector<double> warm;
    for (const double view_weight : view_grid) {
      lo.view_weight = view_weight;
      std::vector<double> acc(options.l2_grid.size(), 0.0);
      ViewWeightTrial trial{view_weight, 0, -1, 0};
      Fit chosen;
      for (size_t i : order) {
        lo.l2 = options.l2_grid[i];
        Fit f = fit_rows(d, fit_part, lo, warm);
        acc[i] = accuracy(d, f, val_rows);
        if (acc[i] > trial.accuracy) {  // ties keep the earlier, larger l2
          trial.accuracy = acc[i];
          trial.l2 = lo.l2;
          chosen = f;
        }
        warm = std::move(f.theta);
      }
      trial.agreement = view_agreement(d, chosen, val_pairs);
      p.view_trials.push_back(trial);
      accuracies.push_back(std::move(acc));
      thetas.push_back(std::move(chosen.theta));
    }
    const size_t pick = pick_view_weight(p.view_trials, options.min_view_agreement);
    p.l2 = p.view_trials[pick].l2;
    p.view_weight = p.view_trials[pick].view_weight;
    p.validation_accuracy = std::move(accuracies[pick]);
    best_theta = std::move(thetas[pick]);
    if (d.view_pairs.empty()) p.view_trials.clear();
  } else {
    p.l2 = options.l2_grid.size() == 1 ? options.l2_grid[0] : kFallbackL2;
    p.view_weight = view_grid.front();  // without validation: the smallest
    char buf[160];
    std::snprintf(buf, sizeof buf, "no validation split (%zu group%s, %zu l2 candidate%s); l2=%g",
                  n_groups, n_groups == 1 ? "" : "s", options.l2_grid.size(),
                  options.l2_grid.size() == 1 ? "" : "s", p.l2);
    p.note = buf;
    if (p.view_weight > 0) {
      std::snprintf(buf, sizeof buf, ", view weight %g", p.view_weight);
      p.note += buf;
    }
  }
  lo.view_weight = p.view_weight;
  lo.l2 = p.l2;
  // Warm start from the chosen strength's validation fit: its standardisation differs only by
  // the validation rows, so the optimum is near (same optimum, fewer iterations).
  Fit f = fit_rows(d, all_rows, lo, std::move(best_theta));
  record_convergence(f, lo, p);
  p.train_accuracy = accuracy(d, f, all_rows);
  p.weight = std::move(f.weight);
  p.bias = std::move(f.bias);
  return p;
}

}  // namespace tlvlink::eval
