#include "tlvlink/daemon/model_check.h"

#include "tlvlink/executor.h"
#include "tlvlink/model.h"
#include "tlvlink/model_integrity.h"
#include "tlvlink/pipeline/frame_processor.h"
#include "tlvlink/verify/golden.h"

namespace tlvlink::daemon {

Result<std::unique_ptr<Model>> load_config_model(const DaemonConfig& config) {
  LoadOptions load;
  PublicKey key;
  if (!config.model_public_key.empty()) {
    auto read = read_public_key_file(config.model_public_key.c_str());
    if (!read.ok()) return read.error().with_context("model_public_key");
    key = *read;
    load.public_key = &key;
  }
  auto model = Model::load_file(config.model.c_str(), load);
  if (model.ok()) return model;
  if (load.public_key != nullptr && model.error().code() == ErrorCode::kModelSignature) {
    return model.error().with_context("model %s, model_public_key %s", config.model.c_str(),
                                      config.model_public_key.c_str());
  }
  return model.error().with_context("model %s", config.model.c_str());
}

Result<ModelCheck> check_model(const DaemonConfig& config) {
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Model> model, load_config_model(config));
  const Model& m = *model;
  TLV_ASSIGN_OR_RETURN(const ExecutorKind kind, parse_executor_kind(config.executor));
  ExecutorOptions options;
  options.threads = config.threads;
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Executor> executor, make_executor(m, kind, options));
  ModelCheck out;
  out.model_name = std::string(m.metadata().name);
  out.golden_pairs = m.metadata().golden.size();
  if (out.golden_pairs > 0) {
    auto report = verify::verify_golden(m, *executor);
    if (!report.ok()) return report.error().with_context("verifying %s", config.model.c_str());
    out.golden_pass = report->pass;  // includes the stored head outputs
    for (const verify::PairResult& p : report->pairs) {
      if (p.comparison.max_abs_error >= out.max_error) {
        out.max_error = p.comparison.max_abs_error;
        out.tolerance = p.comparison.tolerance;
      }
    }
  }
  std::vector<pipeline::SensorSetup> setups;
  for (const SensorConfig& c : config.sensors) {
    setups.push_back({c.name, c.view.width, c.view.height, 3, c.finger, c.sensor_model});
  }
  auto processor = pipeline::FrameProcessor::create(m, *executor, setups, config.processing);
  if (!processor.ok()) return processor.error().with_context("%s", config.path.c_str());
  const auto results = (*processor)->heads().results();
  for (int16_t h : (*processor)->reported_heads()) {
    out.reported_heads.emplace_back(results[static_cast<size_t>(h)].name);
  }
  if ((*processor)->tracks_grasps())
    out.grasp_head = heads::grasp_head_label((*processor)->heads(), (*processor)->grasp_head());
  return out;
}

}  // namespace tlvlink::daemon
