// tlvlink export CKPT -o MODEL.tlvm: a trained checkpoint as a float .tlvm (BatchNorm folded,
// zero-shot heads from the training text encoder). Built with TLVLINK_BUILD_TRAINER.

#include <cstdio>
#include <memory>

#include "common.h"
#include "tlvlink/io/format.h"
#include "tlvlink/trainer/trainer.h"

namespace tlvlink::cli {

void add_export_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<trainer::ExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Export a `tlvlink train` checkpoint to a float .tlvm (BatchNorm folded, input "
      "spec, zero-shot heads, provenance)");
  cmd->add_option("checkpoint", o->checkpoint, "Checkpoint written by tlvlink train")->required();
  cmd->add_option("-o,--output", o->output, "Model file to write (.tlvm)")->required();
  cmd->add_option("--text-embeddings", o->text_embeddings,
                  "Precomputed text embeddings directory, if it moved since training");
  cmd->add_option("--name", o->name, "Model name (default tlvlink-<arch>-<H>x<W>-fp32)");
  cmd->add_option("--golden-data", o->golden_data,
                  "Touch100k set whose test split gives the golden frames (default: the "
                  "training set recorded in the checkpoint)");
  cmd->add_option("--golden-frames", o->golden_frames,
                  "Golden I/O pairs to embed (libtorch outputs; `tlvlink verify` replays them)")
      ->check(CLI::Range(0, trainer::kMaxGoldenFrames))
      ->capture_default_str();
  cmd->footer(kExitCodeFooter);
  cmd->callback([o, &exit_code] {
    auto s = trainer::export_model(*o);
    if (!s.ok()) {
      exit_code = report_error("export", s.error());
      return;
    }
    std::string heads;
    for (const std::string& h : s->zero_shot_heads) heads += (heads.empty() ? "" : ", ") + h;
    std::printf("exported %s\n  %s, %s, embedding %d, zero-shot heads: %s, %d golden pairs\n",
                o->output.c_str(), s->arch_description.c_str(),
                tools::human_bytes(s->file_bytes).c_str(), s->embedding_dim, heads.c_str(),
                s->golden_pairs);
    if (!s->note.empty()) std::printf("  note: %s\n", s->note.c_str());
    exit_code = kExitOk;
  });
}

}  // namespace tlvlink::cli
