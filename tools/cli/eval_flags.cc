#include "eval_flags.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace tlvlink::cli {

void EvalFlags::add_to(CLI::App& app) {
  app.add_option("--touch", touch,
                 "Touch dataset dir: Touch100k (data_list.json; labels from the simulator's "
                 "sidecar) or Touch-and-Go (train.txt/test.txt label files)");
  app.add_option("--touch-format", touch_format, "auto, touch100k or tag")
      ->check(CLI::IsMember({"auto", "touch100k", "tag"}))
      ->capture_default_str();
  app.add_option("--grasp", grasp,
                 "Grasp dataset: Feel HDF5 dir (or one .h5 file) or TLV-Link's repacked layout");
  app.add_option("--grasp-format", grasp_format, "auto, hdf5 or repacked")
      ->check(CLI::IsMember({"auto", "hdf5", "repacked"}))
      ->capture_default_str();
  app.add_option("--resplit", resplit,
                 "Split by a hash of the session/object with this test fraction (default: the "
                 "recorded split of a generated set, else 0.2)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--split-seed", split_seed, "Seed of the hash split")->capture_default_str();
  app.add_option(
      "--problems", problems,
      "Write every load problem (file:line: kind: reason) to FILE; stderr shows the first 10");
  app.add_option("--train-jpeg", train_jpeg,
                 "Also fit on the touch train frames saved as JPEG at these qualities (e.g. "
                 "75,90): heads fitted across the codec paths a board's frames take")
      ->delimiter(',');
  app.add_flag("--train-live", train_live,
               "Also fit on the touch train frames through their sensor's live path (the "
               "simulated camera's raw output decoded as tlvlinkd decodes it; simulated sets)");
  app.add_option("--touch-from-grasps", touch_from_grasps,
                 "Also fit the touch heads on the training grasps of this simulated Feel set: "
                 "each finger's frame during the grasp, labelled with the object's material");
  app.add_option("--view-weight", view_weights,
                 "With --train-jpeg / --train-live: penalise each touch head's logit change "
                 "between a train frame and its re-encodings by this weight (0 = off), so a "
                 "codec moves its answer less; several (e.g. 0,1,3,10): chosen on the validation "
                 "split, by accuracy or by --min-view-agreement; TASK=W (e.g. rough_smooth=10) "
                 "sets one head's (repeat for a grid)")
      ->delimiter(',');
  app.add_option("--min-view-agreement", min_view_agreement,
                 "With several --view-weight: take the smallest whose head gives a validation "
                 "frame and its re-encodings the same answer on at least this share of pairs "
                 "(e.g. 0.95; none reaches it: the most agreeing); 0 = the most accurate")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--max-touch", max_touch, "Touch samples per split (0 = all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--max-grasp", max_grasp, "Grasp episodes per split (0 = all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--jpeg-scale", jpeg_scale, "Decode JPEGs at 1/N size (1, 2, 4, 8)")
      ->check(CLI::IsMember({1, 2, 4, 8}))
      ->capture_default_str();
  app.add_option("--quarter-turns", quarter_turns,
                 "Feel HDF5: undo the stored rotation of the GelSight frames (0-3)")
      ->check(CLI::Range(0, 3))
      ->capture_default_str();
  app.add_option("--grasp-features", grasp_features,
                 "Grasp probe features: before-during-difference (before + during embeddings "
                 "and how each finger's image changed between them), before-during (A/B "
                 "before + during, Calandra) or before-after (TLV-Link parity)")
      ->check(CLI::IsMember({"before-during-difference", "before-during", "before-after"}))
      ->capture_default_str();
  app.add_option("--l2", l2_grid,
                 "Comma-separated L2 strengths to choose from on a validation split by "
                 "session/object (default 1e-4,1e-3,1e-2,0.1,1,10; one value: no validation)");
  app.add_option("--max-iterations", max_iterations, "L-BFGS iterations per fit")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--zero-shot", zero_shot,
                 "Zero-shot heads: auto (the model's, else from the text encoder), model, text")
      ->check(CLI::IsMember({"auto", "model", "text"}))
      ->capture_default_str();
  app.add_option("--text-embeddings", text_embeddings,
                 "Precomputed text embeddings dir for zero-shot heads (tools/text layout)");
  app.add_option("--text-seed", text_seed,
                 "Built-in hashing text encoder seed (default: the model's recorded encoder, "
                 "else 7)");
  app.add_option("--oracle-samples", oracle_samples,
                 "Monte Carlo episodes of the grasp oracle for generated sets (0 = skip it and the "
                 "grasp frames estimate)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_flag("--quiet,-q", quiet, "No progress on stderr");
  exec.add_to(app,
              "Threads: the datasets' frames are loaded beside N embedded at once, each on one "
              "executor thread, and up to N heads' probes fitted side by side (the same figures "
              "for any N); --images / --recordings: XNNPACK's pool");
}

Result<eval::EvalData> EvalFlags::data() const {
  eval::EvalData d;
  d.touch_dir = touch;
  d.grasp_dir = grasp;
  d.touch_format = touch_format == "touch100k" ? eval::TouchFormat::kTouch100k
                   : touch_format == "tag"     ? eval::TouchFormat::kTouchAndGo
                                               : eval::TouchFormat::kAuto;
  d.grasp_format = grasp_format == "hdf5"       ? eval::GraspFormat::kFeelHdf5
                   : grasp_format == "repacked" ? eval::GraspFormat::kFeelRepacked
                                                : eval::GraspFormat::kAuto;
  if (resplit >= 0) d.resplit = datasets::HashSplit{resplit, split_seed};
  d.default_split.seed = split_seed;
  d.scale_denominator = jpeg_scale;
  d.gelsight_quarter_turns = quarter_turns;
  d.max_touch_samples = max_touch;
  d.train_jpeg_qualities = train_jpeg;
  d.train_live_path = train_live;
  d.touch_from_grasps_dir = touch_from_grasps;
  d.max_grasp_episodes = max_grasp;
  TLV_ENSURE(!touch.empty() || !grasp.empty(), ErrorCode::kInvalidArgument,
             "give a dataset: --touch DIR and/or --grasp DIR");
  TLV_ENSURE(touch_from_grasps.empty() || !touch.empty(), ErrorCode::kInvalidArgument,
             "--touch-from-grasps needs --touch: the grasps' frames are extra training rows of "
             "the touch heads, whose test split is the touch set's");
  return d;
}

Status EvalFlags::parse_view_weights(eval::HeadFitOptions& heads) const {
  std::vector<double> shared;
  bool penalised = false;
  for (const std::string& item : view_weights) {
    const size_t eq = item.find('=');
    const std::string number = eq == std::string::npos ? item : item.substr(eq + 1);
    char* end = nullptr;
    const double w = std::strtod(number.c_str(), &end);
    TLV_ENSURE(
        !number.empty() && end == number.c_str() + number.size() && std::isfinite(w) && w >= 0,
        ErrorCode::kInvalidArgument, "--view-weight: '%s' is not W or TASK=W with W >= 0",
        item.c_str());
    penalised = penalised || w > 0;
    if (eq == std::string::npos) {
      shared.push_back(w);
      continue;
    }
    Result<eval::Task> parsed = eval::parse_task(item.substr(0, eq));
    if (!parsed.ok()) return parsed.error().with_context("--view-weight %s", item.c_str());
    const eval::Task task = *parsed;
    TLV_ENSURE(task != eval::Task::kGrasp, ErrorCode::kInvalidArgument,
               "--view-weight %s: only touch heads have views (material, hard_soft, "
               "rough_smooth)",
               item.c_str());
    heads.view_weight_grid_of[task].push_back(w);
  }
  TLV_ENSURE(!penalised || !train_jpeg.empty() || train_live, ErrorCode::kInvalidArgument,
             "--view-weight needs --train-jpeg or --train-live: the re-encodings are the second "
             "views");
  if (!shared.empty()) heads.probe.view_weight_grid = shared;
  return {};
}

Result<eval::EvalOptions> EvalFlags::options() const {
  eval::EvalOptions o;
  TLV_ASSIGN_OR_RETURN(o.embedder.executor, parse_executor_kind(exec.executor));
  o.embedder.threads = exec.threads;
  o.heads.threads = exec.threads;
  o.embedder.progress = !quiet;
  TLV_ASSIGN_OR_RETURN(o.heads.grasp_features, eval::parse_grasp_features(grasp_features));
  if (!l2_grid.empty()) {
    o.heads.probe.l2_grid.clear();
    size_t start = 0;
    while (start <= l2_grid.size()) {
      const size_t comma = std::min(l2_grid.find(',', start), l2_grid.size());
      const std::string item = l2_grid.substr(start, comma - start);
      char* end = nullptr;
      const double v = std::strtod(item.c_str(), &end);
      TLV_ENSURE(!item.empty() && end == item.c_str() + item.size() && std::isfinite(v) && v >= 0,
                 ErrorCode::kInvalidArgument, "--l2: '%s' is not a finite number >= 0",
                 item.c_str());
      o.heads.probe.l2_grid.push_back(v);
      start = comma + 1;
    }
  }
  o.heads.probe.logistic.max_iterations = max_iterations;
  TLV_TRY(parse_view_weights(o.heads));
  const bool several =
      o.heads.probe.view_weight_grid.size() > 1 ||
      std::any_of(o.heads.view_weight_grid_of.begin(), o.heads.view_weight_grid_of.end(),
                  [](const auto& g) { return g.second.size() > 1; });
  TLV_ENSURE(min_view_agreement == 0 || several, ErrorCode::kInvalidArgument,
             "--min-view-agreement %g needs several --view-weight values to choose from",
             min_view_agreement);
  o.heads.probe.min_view_agreement = min_view_agreement;
  o.zero_shot = zero_shot == "model"  ? eval::ZeroShotSource::kModel
                : zero_shot == "text" ? eval::ZeroShotSource::kText
                                      : eval::ZeroShotSource::kAuto;
  o.text.precomputed_dir = text_embeddings;
  if (text_seed >= 0) o.text.hashing_seed = static_cast<uint64_t>(text_seed);
  o.oracle_samples = oracle_samples;
  return o;
}

}  // namespace tlvlink::cli
