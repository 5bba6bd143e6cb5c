#include "tlvlink/stream/hello.h"

#include "tlvlink/stream/stages.h"

namespace tlvlink::stream {

HelloBuilder::HelloBuilder(const BoardIdentity& board, const Model& model,
                           std::string_view model_id_fallback,
                           std::span<const SensorDescription> sensors, const OutputNames& names) {
  const std::string_view device = strings_.emplace_back(board.device);
  const std::string_view board_name = strings_.emplace_back(board.board);
  const std::string_view version = strings_.emplace_back(board.firmware_version);
  const std::string_view model_id =
      strings_.emplace_back(model.metadata().name.empty() ? std::string(model_id_fallback)
                                                          : std::string(model.metadata().name));
  for (size_t i = 0; i < sensors.size(); ++i) {
    const SensorDescription& s = sensors[i];
    protocol::SensorInfo info;
    info.index = static_cast<uint8_t>(i);
    info.name = strings_.emplace_back(s.name);
    info.model = strings_.emplace_back(s.model);
    info.serial = "";
    info.pixel_format = strings_.emplace_back(s.pixel_format);
    info.width = static_cast<uint16_t>(s.width);
    info.height = static_cast<uint16_t>(s.height);
    info.fps = static_cast<float>(s.fps);
    sensors_.push_back(info);
  }
  // The labels' views point into `names`' strings, copied here first.
  label_views_.reserve(names.heads.size());
  for (const OutputNames::Head& h : names.heads) {
    std::vector<std::string_view>& labels = label_views_.emplace_back();
    for (const std::string& l : h.labels) labels.push_back(strings_.emplace_back(l));
    protocol::HeadInfo info;
    info.name = strings_.emplace_back(h.name);
    info.kind = h.kind == "zero-shot" ? protocol::HeadKind::kZeroShot : protocol::HeadKind::kLinear;
    info.labels = labels;
    info.accuracy = h.accuracy;  // NaN (protocol::kNotRecorded) when the model has no record
    info.majority_rate = h.majority;
    info.accuracy_ci_low = h.ci_low;
    info.accuracy_ci_high = h.ci_high;
    info.balanced_accuracy = h.balanced;
    info.baseline_accuracy = h.baseline;
    info.groups = h.groups;
    heads_.push_back(info);
  }
  if (!names.grasp_head.empty()) {
    protocol::HeadInfo grasp;
    grasp.name = strings_.emplace_back(names.grasp_head);
    grasp.kind = protocol::HeadKind::kGrasp;
    grasp.accuracy = names.grasp.accuracy;
    grasp.majority_rate = names.grasp.majority;
    heads_.push_back(grasp);
  }
  for (const char* s : kStageNames) stage_names_.emplace_back(s);
  hello_.device = device;
  hello_.board = board_name;
  hello_.firmware_version = version;
  hello_.boot_id = board.boot_id;
  hello_.model_id = model_id;
  hello_.model_checksum = model.metadata().provenance.content_checksum;
  hello_.sensors = sensors_;
  hello_.heads = heads_;
  hello_.stage_names = stage_names_;
  hello_.embedding_dim = static_cast<uint16_t>(model.metadata().embedding_dim);
}

}  // namespace tlvlink::stream
