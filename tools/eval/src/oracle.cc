// Touch-task oracles from the simulator's recorded hidden variables (oracle.h).

#include "tlvlink/eval/oracle.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include "tlvlink/sim/generate.h"

namespace tlvlink::eval {
namespace {

constexpr int32_t kFrameFeatures = 6;
// Logs of quantities that can be 0 (no contact, a texture-free glass) are floored here: far
// below anything a frame resolves (mm^2, mm, um, N).
constexpr double kLogFloor = 1e-6;

// Density of x under a log-uniform prior on [lo, hi] (0 outside; a point range is accepted
// with density 1 at that point).
double log_uniform_density(double x, sim::Range r) {
  if (r.hi <= r.lo) return x == r.lo ? 1.0 : 0.0;
  if (x < r.lo || x > r.hi) return 0.0;
  return 1.0 / (x * std::log(r.hi / r.lo));
}

double uniform_density(double x, sim::Range r) {
  if (r.hi <= r.lo) return x == r.lo ? 1.0 : 0.0;
  if (x < r.lo || x > r.hi) return 0.0;
  return 1.0 / (r.hi - r.lo);
}

// Recorded parameters are printed with ~17 digits and so sit inside their ranges, but a value
// drawn at a range's end may round just outside: widen each range by this relative margin.
constexpr double kRangeSlack = 1e-9;
sim::Range widen(sim::Range r) {
  return {r.lo - kRangeSlack * std::fabs(r.lo), r.hi + kRangeSlack * std::fabs(r.hi)};
}

// What a texture shows in the frame: its shading contrast, ~ the renderer's small-slope gain
// (80 DN at 45 deg: ~80 DN per radian, tools/sim/REFERENCE.md "Shading") times its rms slope
// Sq / lc. Below kVisibleTextureDn (a third of the camera noise sigma of 3 DN, under the camera's
// 5x5 blur) the frame's noise hides it: then neither its amplitude nor its correlation length
// nor its Hurst exponent can be read from the frame, and all three take one "invisible" value.
constexpr double kShadingDnPerRadian = 80.0;
constexpr double kVisibleTextureDn = 1.0;

void frame_features(const sim::MaterialSample& m, const sim::ContactState& c, double* f) {
  // texture_kappa is 0 in sets written before it was recorded: then the texture followed the
  // bulk split kappa.
  const double tk = c.texture_kappa > 0 ? c.texture_kappa : c.kappa;
  f[0] = std::log(std::max(c.force_n, kLogFloor));
  f[1] = std::log(std::max(c.contact_area_mm2, kLogFloor));
  f[2] = std::log(std::max(c.max_gel_indentation_mm, kLogFloor));
  const double contrast_dn =
      kShadingDnPerRadian * tk * m.sq_um * 1e-3 / std::max(m.correlation_length_mm, kLogFloor);
  const bool visible = contrast_dn >= kVisibleTextureDn;
  f[3] = std::log(visible ? contrast_dn : kVisibleTextureDn);
  f[4] = visible ? m.correlation_length_mm : 0.0;
  f[5] = visible ? m.hurst : 0.0;
}

int32_t label_of(const TouchEmbeddings& t, Task task, size_t i) {
  return task == Task::kMaterial ? t.material[i] : task == Task::kHard ? t.hard[i] : t.rough[i];
}

}  // namespace

namespace {

// Likelihood of each class for the recorded parameters (the product of their prior densities).
std::array<double, sim::kMaterialClassCount> material_likelihoods(const sim::MaterialSample& m) {
  std::array<double, sim::kMaterialClassCount> p{};
  for (const sim::MaterialClass& c : sim::material_classes()) {
    p[static_cast<size_t>(c.id)] =
        log_uniform_density(m.modulus_pa, widen(c.modulus_pa)) *
        uniform_density(m.poisson, widen(c.poisson)) *
        uniform_density(m.friction, widen(c.friction)) *
        log_uniform_density(m.sq_um, widen(c.sq_um)) *
        uniform_density(m.correlation_length_mm, widen(c.correlation_length_mm)) *
        uniform_density(m.hurst, widen(c.hurst));
  }
  return p;
}

}  // namespace

int32_t bayes_material_class(const sim::MaterialSample& m, int32_t* tied) {
  const auto p = material_likelihoods(m);
  double best = 0;
  int32_t best_class = -1, ties = 0;
  for (int32_t c = 0; c < sim::kMaterialClassCount; ++c) {
    const double v = p[static_cast<size_t>(c)];
    if (v <= 0) continue;
    if (v > best) {
      best = v;
      best_class = c;
      ties = 1;
    } else if (v == best) {
      ++ties;
    }
  }
  if (tied != nullptr) *tied = best_class < 0 ? 0 : ties;
  return best_class;
}

namespace {

// Mean and 1 / std of each feature over the reference rows: distances in standard units.
struct FeatureScale {
  std::vector<double> mean, scale;
};

FeatureScale feature_scale(std::span<const double> rows, size_t d) {
  const size_t n = rows.size() / d;
  FeatureScale s{std::vector<double>(d, 0.0), std::vector<double>(d, 1.0)};
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < d; ++j) s.mean[j] += rows[i * d + j];
  for (size_t j = 0; j < d && n > 0; ++j) s.mean[j] /= static_cast<double>(n);
  for (size_t j = 0; j < d && n > 1; ++j) {
    double ss = 0;
    for (size_t i = 0; i < n; ++i)
      ss += (rows[i * d + j] - s.mean[j]) * (rows[i * d + j] - s.mean[j]);
    const double sd = std::sqrt(ss / static_cast<double>(n - 1));
    s.scale[j] = sd > 0 ? 1.0 / sd : 1.0;  // a constant feature carries nothing: left unscaled
  }
  return s;
}

double squared_distance(const double* a, const double* b, const FeatureScale& s, size_t d) {
  double sum = 0;
  for (size_t j = 0; j < d; ++j) {
    const double v = (a[j] - b[j]) * s.scale[j];
    sum += v * v;
  }
  return sum;
}

}  // namespace

std::vector<int32_t> knn_predict(std::span<const double> train, std::span<const int32_t> labels,
                                 std::span<const double> query, int32_t dims, int32_t classes,
                                 int32_t k) {
  const auto d = static_cast<size_t>(dims);
  const size_t n = labels.size(), q = query.size() / d;
  const FeatureScale scale = feature_scale(train.first(n * d), d);
  const size_t kk = std::min(static_cast<size_t>(std::max(k, 1)), n);
  std::vector<int32_t> out(q, 0);
  std::vector<std::pair<double, int32_t>> dist(n);
  std::vector<int32_t> votes(static_cast<size_t>(classes));
  std::vector<double> near(static_cast<size_t>(classes));
  for (size_t r = 0; r < q && n > 0; ++r) {
    for (size_t i = 0; i < n; ++i)
      dist[i] = {squared_distance(&train[i * d], &query[r * d], scale, d), labels[i]};
    std::partial_sort(dist.begin(), dist.begin() + static_cast<std::ptrdiff_t>(kk), dist.end());
    std::fill(votes.begin(), votes.end(), 0);
    std::fill(near.begin(), near.end(), 0.0);
    for (size_t i = 0; i < kk; ++i) {
      ++votes[static_cast<size_t>(dist[i].second)];
      near[static_cast<size_t>(dist[i].second)] += std::sqrt(dist[i].first);
    }
    int32_t best = 0;
    for (int32_t c = 1; c < classes; ++c) {
      const auto bc = static_cast<size_t>(best), cc = static_cast<size_t>(c);
      if (votes[cc] > votes[bc] || (votes[cc] == votes[bc] && votes[cc] > 0 && near[cc] < near[bc]))
        best = c;
    }
    out[r] = best;
  }
  return out;
}

std::vector<std::array<double, sim::kMaterialClassCount>> knn_class_weights_other_groups(
    std::span<const double> rows, std::span<const int32_t> classes,
    std::span<const std::string> groups, std::span<const size_t> queries, int32_t dims, int32_t k) {
  const auto d = static_cast<size_t>(dims);
  const size_t n = classes.size();
  const FeatureScale scale = feature_scale(rows.first(n * d), d);
  std::vector<std::array<double, sim::kMaterialClassCount>> out(queries.size());
  std::vector<std::pair<double, int32_t>> dist;
  dist.reserve(n);
  for (size_t r = 0; r < queries.size(); ++r) {
    const size_t q = queries[r];
    dist.clear();
    for (size_t i = 0; i < n; ++i) {
      if (groups[i] == groups[q]) continue;  // never the query's own object
      dist.emplace_back(squared_distance(&rows[i * d], &rows[q * d], scale, d), classes[i]);
    }
    out[r].fill(0.0);
    const size_t kk = std::min(static_cast<size_t>(std::max(k, 1)), dist.size());
    if (kk == 0) continue;
    std::partial_sort(dist.begin(), dist.begin() + static_cast<std::ptrdiff_t>(kk), dist.end());
    for (size_t i = 0; i < kk; ++i)
      out[r][static_cast<size_t>(dist[i].second)] += 1.0 / static_cast<double>(kk);
  }
  return out;
}

std::vector<TouchOracle> touch_oracles(const TouchEmbeddings& t) {
  std::vector<TouchOracle> out;
  const bool recorded = t.hidden_material.size() == t.size() && t.hidden_contact.size() == t.size();
  for (Task task : {Task::kMaterial, Task::kHard, Task::kRough}) {
    TouchOracle o;
    o.task = task;
    if (!recorded) {
      o.note = "no hidden variables recorded";
      out.push_back(o);
      continue;
    }
    std::vector<double> train, query;
    std::vector<int32_t> train_labels, query_labels;
    double hidden_correct = 0;
    double f[kFrameFeatures];
    for (size_t i = 0; i < t.size(); ++i) {
      const sim::MaterialSample& m = t.hidden_material[i];
      const int32_t label = label_of(t, task, i);
      if (m.class_id < 0 || label < 0) continue;
      frame_features(m, t.hidden_contact[i], f);
      if (t.is_test[i] == 0) {
        train.insert(train.end(), f, f + kFrameFeatures);
        train_labels.push_back(label);
        continue;
      }
      query.insert(query.end(), f, f + kFrameFeatures);
      query_labels.push_back(label);
      if (task == Task::kMaterial) {
        // With several classes equally likely the oracle guesses among them: count its
        // expected share when the true class is one of them.
        int32_t ties = 0;
        const int32_t c = bayes_material_class(m, &ties);
        const auto p = material_likelihoods(m);
        if (c >= 0 && p[static_cast<size_t>(label)] == p[static_cast<size_t>(c)])
          hidden_correct += 1.0 / ties;
      } else {
        // The label is the physics rule of the recorded variable (materials.h): always right.
        const int32_t rule = task == Task::kHard ? (sim::hard_label(m.modulus_pa) ? 1 : 0)
                                                 : sim::rough_label(m.sq_um);
        hidden_correct += rule == label ? 1.0 : 0.0;
      }
    }
    o.n = static_cast<int64_t>(query_labels.size());
    if (o.n == 0 || train_labels.empty()) {
      o.note = o.n == 0 ? "no labelled test item with hidden variables"
                        : "no labelled training item with hidden variables";
      out.push_back(o);
      continue;
    }
    o.available = true;
    o.hidden_accuracy = hidden_correct / static_cast<double>(o.n);
    const std::vector<int32_t> pred = knn_predict(train, train_labels, query, kFrameFeatures,
                                                  task_class_count(task), kFrameOracleNeighbours);
    int64_t correct = 0;
    for (size_t i = 0; i < pred.size(); ++i) correct += pred[i] == query_labels[i] ? 1 : 0;
    o.frame_accuracy = static_cast<double>(correct) / static_cast<double>(o.n);
    out.push_back(o);
  }
  return out;
}

Result<GraspFramesOracle> grasp_frames_oracle(const GraspEmbeddings& g) {
  GraspFramesOracle o;
  const bool recorded = g.hidden_material.size() == g.size() &&
                        g.hidden_variables.size() == g.size() && g.hidden_during.size() == g.size();
  std::vector<double> rows;
  std::vector<int32_t> classes;
  std::vector<std::string> groups;
  std::vector<size_t> queries;
  std::vector<sim::GraspVariables> variables;
  std::vector<int32_t> labels;
  constexpr int32_t kDims = heads::kFingers * kFrameFeatures;
  double f[kDims];
  for (size_t i = 0; recorded && i < g.size(); ++i) {
    const sim::MaterialSample& m = g.hidden_material[i];
    if (m.class_id < 0) continue;
    for (int32_t finger = 0; finger < heads::kFingers; ++finger)
      frame_features(m, g.hidden_during[i][static_cast<size_t>(finger)],
                     f + finger * kFrameFeatures);
    if (g.is_test[i] != 0) {
      queries.push_back(classes.size());
      variables.push_back(g.hidden_variables[i]);
      labels.push_back(g.label[i]);
    }
    rows.insert(rows.end(), f, f + kDims);
    classes.push_back(m.class_id);
    groups.push_back(g.group[i]);
  }
  o.n = static_cast<int64_t>(queries.size());
  if (o.n == 0) {
    o.note = "no test episode with recorded variables";
    return o;
  }
  const auto weights =
      knn_class_weights_other_groups(rows, classes, groups, queries, kDims, kFrameOracleNeighbours);
  std::vector<std::array<double, sim::kMaterialClassCount>> truth(queries.size());
  for (size_t r = 0; r < queries.size(); ++r) {
    truth[r].fill(0.0);
    truth[r][static_cast<size_t>(classes[queries[r]])] = 1.0;
  }
  constexpr uint64_t kHiddenSeed = 1;  // the hidden variables' draws, as the oracle's
  TLV_ASSIGN_OR_RETURN(const auto p_frames,
                       sim::grasp_success_given_class_weights(variables, weights, kHiddenSeed));
  TLV_ASSIGN_OR_RETURN(const auto p_class,
                       sim::grasp_success_given_class_weights(variables, truth, kHiddenSeed));
  int64_t frames_ok = 0, class_ok = 0, successes = 0;
  for (size_t r = 0; r < labels.size(); ++r) {
    const bool y = labels[r] == 1;
    frames_ok += (p_frames[r] > 0.5) == y ? 1 : 0;
    class_ok += (p_class[r] > 0.5) == y ? 1 : 0;
    successes += y ? 1 : 0;
  }
  const auto n = static_cast<double>(o.n);
  o.available = true;
  o.frames_accuracy = static_cast<double>(frames_ok) / n;
  o.class_accuracy = static_cast<double>(class_ok) / n;
  o.majority_rate =
      std::max(static_cast<double>(successes), n - static_cast<double>(successes)) / n;
  return o;
}

}  // namespace tlvlink::eval
