// tlvlink train DATA_DIR -o OUT.ckpt: TLV-Link training of an edge touch encoder (libtorch).
// Built with TLVLINK_BUILD_TRAINER; see tools/trainer/README.md.

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "common.h"
#include "tlvlink/trainer/arch.h"
#include "tlvlink/trainer/trainer.h"

namespace tlvlink::cli {
namespace {

struct TrainFlags {
  trainer::TrainOptions o;
  std::string beta_schedule = "linear";
  std::string objective = "tlv-link";
  std::string resize = "bilinear";
  std::string view = "none";
  bool no_curriculum = false;
  bool list_archs = false;
  int64_t max_cache_mb = static_cast<int64_t>(trainer::kDefaultMaxCacheBytes >> 20);
  std::vector<CLI::Option*> settings;  // result-determining flags (not allowed with --resume)
};

int list_archs(const trainer::TrainOptions& o) {
  const std::string names = trainer::arch_names();
  for (size_t start = 0; start < names.size();) {
    const size_t comma = std::min(names.find(", ", start), names.size());
    const std::string name = names.substr(start, comma - start);
    start = comma + 2;
    auto a = trainer::make_arch(name, o.input_height, o.input_width, o.text.dim);
    if (!a.ok()) return report_error("train", a.error());
    std::printf("%s\n", trainer::describe_arch(*a).c_str());
  }
  return kExitOk;
}

int run_train(TrainFlags& f) {
  if (f.list_archs) return list_archs(f.o);
  if (f.o.data_dir.empty() || f.o.output.empty()) {
    std::fprintf(stderr, "tlvlink train: DATA_DIR and -o OUT.ckpt are required\n");
    return kExitUsage;
  }
  if (!f.o.resume.empty()) {
    for (const CLI::Option* opt : f.settings) {
      if (opt->count() > 0) {
        std::fprintf(stderr,
                     "tlvlink train: %s cannot be combined with --resume (a resumed run uses the "
                     "checkpoint's settings)\n",
                     opt->get_name().c_str());
        return kExitUsage;
      }
    }
  }
  auto objective = trainer::parse_objective(f.objective);
  if (!objective.ok()) return report_error("train", objective.error());
  f.o.objective = *objective;
  f.o.resize = f.resize == "area" ? ResizeFilter::kArea : ResizeFilter::kBilinear;
  auto view = trainer::parse_view_components(f.view);
  if (!view.ok()) return report_error("train", view.error());
  f.o.view.components = *view;
  // The supervised objective has no text loss, so no curriculum (and no teacher) either.
  const bool no_curriculum = f.no_curriculum || *objective == trainer::Objective::kSupervised;
  auto schedule = trainer::parse_beta_schedule(no_curriculum ? "none" : f.beta_schedule);
  if (!schedule.ok()) return report_error("train", schedule.error());
  f.o.beta.schedule = *schedule;
  f.o.max_cache_bytes = static_cast<size_t>(f.max_cache_mb) << 20;
  auto summary = trainer::train(f.o);
  if (!summary.ok()) return report_error("train", summary.error());
  const trainer::TrainSummary& s = *summary;
  std::printf("trained %s\n", s.arch_description.c_str());
  std::printf(
      "  %lld training samples, steps %lld..%lld (%lld per epoch), mean loss first epoch "
      "%.4f, last epoch %.4f, final %.4f\n",
      static_cast<long long>(s.train_samples), static_cast<long long>(s.start_step),
      static_cast<long long>(s.steps), static_cast<long long>(s.steps_per_epoch),
      s.first_epoch_loss, s.last_epoch_loss, s.final_loss);
  std::printf("  student %.1f samples/s; wall: load %.1fs, teacher %.1fs, student %.1fs\n",
              s.student_samples_per_s, s.load_seconds, s.teacher_seconds, s.student_seconds);
  std::printf("  checkpoint %s\n  log %s\n", s.checkpoint.c_str(), s.log_path.c_str());
  return kExitOk;
}

}  // namespace

void add_train_command(CLI::App& app, int& exit_code) {
  auto f = std::make_shared<TrainFlags>();
  trainer::TrainOptions& o = f->o;
  CLI::App* cmd = app.add_subcommand(
      "train",
      "Train an edge touch encoder with TLV-Link (vision teacher, curriculum, InfoNCE "
      "against frozen text features) on a Touch100k-format set");
  auto setting = [&f](CLI::Option* opt) {
    f->settings.push_back(opt);
    return opt;
  };
  cmd->add_option("data", o.data_dir, "Touch100k-format directory (tlvlink sim touch100k -o DIR)");
  cmd->add_option("-o,--output", o.output, "Final checkpoint to write");
  cmd->add_flag("--list-archs", f->list_archs,
                "Print the architectures (MACs, parameters) at the input size and exit");
  setting(cmd->add_option("--arch", o.arch, "Student architecture: " + trainer::arch_names())
              ->capture_default_str());
  setting(cmd->add_option("--input-height", o.input_height, "Model input height")
              ->capture_default_str());
  setting(
      cmd->add_option("--input-width", o.input_width, "Model input width")->capture_default_str());
  setting(cmd->add_option("--epochs", o.epochs, "Epochs over the training split")
              ->capture_default_str());
  setting(cmd->add_option("--max-steps", o.max_steps,
                          "Train exactly this many steps instead (schedules span them; 0 = off)")
              ->capture_default_str());
  setting(cmd->add_option("--batch", o.batch, "Batch size (pairs per InfoNCE batch)")
              ->capture_default_str());
  setting(cmd->add_option("--lr", o.lr.lr, "Peak learning rate (AdamW)")->capture_default_str());
  setting(cmd->add_option("--warmup", o.lr.warmup_steps, "Linear warm-up steps, then cosine decay")
              ->capture_default_str());
  setting(cmd->add_option("--min-lr", o.lr.min_lr, "Learning rate at the end of the decay")
              ->capture_default_str());
  setting(
      cmd->add_option("--weight-decay", o.weight_decay, "AdamW weight decay (conv/FC weights only)")
          ->capture_default_str());
  setting(cmd->add_option("--adam-beta1", o.adam_beta1, "AdamW beta1")->capture_default_str());
  setting(cmd->add_option("--adam-beta2", o.adam_beta2, "AdamW beta2")->capture_default_str());
  setting(cmd->add_option("--adam-eps", o.adam_eps, "AdamW epsilon")->capture_default_str());
  setting(cmd->add_option("--temperature", o.init_temperature,
                          "Initial InfoNCE temperature (learnable)")
              ->capture_default_str());
  setting(
      cmd->add_option("--max-logit-scale", o.max_logit_scale, "Clamp of 1/temperature (CLIP: 100)")
          ->capture_default_str());
  setting(cmd->add_option("--beta-schedule", f->beta_schedule,
                          "Curriculum decay of beta: linear, exponential, cosine")
              ->check(CLI::IsMember({"linear", "exponential", "cosine"}))
              ->capture_default_str());
  setting(cmd->add_option("--beta1", o.beta.beta1, "beta at step 0")->capture_default_str());
  setting(
      cmd->add_option("--beta-span", o.beta.span, "Fraction of all steps over which beta decays")
          ->capture_default_str());
  setting(
      cmd->add_option("--beta-min", o.beta.beta_min, "beta after the span")->capture_default_str());
  setting(cmd->add_flag("--no-curriculum", f->no_curriculum,
                        "beta = 0 throughout (the paper's ablation; no teacher is trained)"));
  setting(cmd->add_option("--objective", f->objective,
                          "What the student learns from: tlv-link (InfoNCE against the text, the "
                          "method), supervised (cross-entropy on the simulator's labels only: the "
                          "supervised upper bound; implies --no-curriculum), tlv-link+supervised "
                          "(both, summed)")
              ->check(CLI::IsMember({"tlv-link", "supervised", "tlv-link+supervised"}))
              ->capture_default_str());
  setting(cmd->add_option("--supervised-weight", o.supervised_weight,
                          "tlv-link+supervised: weight of the cross-entropy term")
              ->capture_default_str());
  setting(cmd->add_option("--contact-weight", o.contact_weight,
                          "supervised objectives: weight of the contact regression (the frame's "
                          "log force and the material's friction, read linearly from the "
                          "embedding; 0 = off)")
              ->check(CLI::Range(0.0, 100.0))
              ->capture_default_str());
  setting(cmd->add_option("--augment-gain", o.augment.gain_sigma,
                          "Augmentation: per-channel gain exp(N(0, s)) around the frame mean "
                          "(0 = off)")
              ->capture_default_str());
  setting(cmd->add_option("--augment-exposure", o.augment.exposure_sigma,
                          "Augmentation: exposure exp(N(0, s)) (0 = off)")
              ->capture_default_str());
  setting(cmd->add_option("--augment-noise", o.augment.noise_dn,
                          "Augmentation: extra camera noise sigma in DN (0 = off)")
              ->capture_default_str());
  setting(cmd->add_option("--resize", f->resize,
                          "The model input's resize from the frame (recorded in the model; the "
                          "board applies it): area averages the frame's pixels into each input "
                          "pixel, so a camera's noise and codec grain do not alias into it")
              ->check(CLI::IsMember({"bilinear", "area"}))
              ->capture_default_str());
  setting(cmd->add_option("--augment-view", f->view,
                          "Sensor-view augmentation at the sensor's frame size: all, none, or a "
                          "comma list of geometry, colour, vignette, led-drift, dust, blur, noise, "
                          "codec (README \"Sensor-view augmentation\")")
              ->capture_default_str());
  setting(cmd->add_option("--consistency-weight", o.view.consistency_weight,
                          "With --augment-view: two views of every sample per step and this "
                          "weight times their embeddings' mean (1 - cosine); 0 = one view")
              ->check(CLI::Range(0.0, 100.0))
              ->capture_default_str());
  setting(cmd->add_option("--prediction-consistency-weight", o.view.prediction_weight,
                          "With two views and a supervised objective: this weight times the "
                          "supervised heads' disagreement between the views (symmetric KL; the "
                          "contact read-out's squared difference); 0 = off")
              ->check(CLI::Range(0.0, 100.0))
              ->capture_default_str());
  setting(cmd->add_option("--codec-pairs", o.view.codec_pairs,
                          "With two views: the share of samples whose second view is the first "
                          "through another codec draw alone (a frame and its re-encoding); "
                          "0 = every pair independent")
              ->check(CLI::Range(0.0, 1.0))
              ->capture_default_str());
  setting(cmd->add_option("--teacher", o.teacher.torchscript,
                          "TorchScript vision encoder (.pt): float [N,3,H,W] RGB normalised by "
                          "--teacher-mean/--teacher-std -> [N,D]; default: the built-in teacher"));
  setting(cmd->add_option("--teacher-arch", o.teacher.builtin_arch, "Built-in teacher architecture")
              ->capture_default_str());
  setting(
      cmd->add_option("--teacher-epochs", o.teacher.epochs, "Built-in teacher pre-training epochs")
          ->capture_default_str());
  setting(cmd->add_option("--teacher-lr", o.teacher.lr, "Built-in teacher peak learning rate")
              ->capture_default_str());
  setting(cmd->add_option("--teacher-input-height", o.teacher.input_height,
                          "TorchScript teacher input height")
              ->capture_default_str());
  setting(cmd->add_option("--teacher-input-width", o.teacher.input_width,
                          "TorchScript teacher input width")
              ->capture_default_str());
  setting(cmd->add_option("--teacher-mean", o.teacher.mean, "TorchScript teacher RGB mean (3)")
              ->delimiter(',')
              ->expected(3));
  setting(cmd->add_option("--teacher-std", o.teacher.std, "TorchScript teacher RGB std (3)")
              ->delimiter(',')
              ->expected(3));
  setting(cmd->add_option("--text-embeddings", o.text.embeddings_dir,
                          "Precomputed text embeddings directory (tools/text/README.md) instead "
                          "of the built-in hashing encoder"));
  setting(cmd->add_option("--text-dim", o.text.dim, "Hashing text encoder dimension")
              ->capture_default_str());
  setting(cmd->add_option("--text-seed", o.text.seed, "Hashing text encoder seed")
              ->capture_default_str());
  setting(
      cmd->add_option("-s,--seed", o.seed, "Seed (weights and data order)")->capture_default_str());
  setting(cmd->add_option("--max-samples", o.max_samples,
                          "Use only the first N training samples (0 = all)")
              ->capture_default_str());
  setting(cmd->add_option("--test-fraction", o.test_fraction,
                          "Held-out share of sessions when the set has no simulator sidecar")
              ->capture_default_str());
  cmd->add_option("-t,--threads", o.threads,
                  "Torch threads; results are reproducible for a fixed count. More than 1 only "
                  "pays on cores nobody else uses (README: 2 threads on a busy 2-core machine "
                  "ran 3x slower)")
      ->capture_default_str();
  cmd->add_option("--max-cache-mb", f->max_cache_mb,
                  "Limit of the in-memory image cache; more is an error")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 20))
      ->capture_default_str();
  cmd->add_option("--checkpoint-dir", o.checkpoint_dir,
                  "Write step_NNNNNNN.ckpt here every --checkpoint-every steps and at the end");
  setting(cmd->add_option("--checkpoint-every", o.checkpoint_every, "Steps between checkpoints")
              ->capture_default_str());
  cmd->add_option("--resume", o.resume, "Continue from this checkpoint (same DATA_DIR)");
  cmd->add_option("--log", o.log_path, "JSON-lines training log (default: OUT.log.jsonl)");
  cmd->footer(kExitCodeFooter);
  cmd->callback([f, &exit_code] { exit_code = run_train(*f); });
}

}  // namespace tlvlink::cli
