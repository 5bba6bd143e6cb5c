// Hello: the board's description, sent at every (re)connect and in answer to Info.
#include <array>

#include "protocol_internal.h"

namespace tlvlink::protocol {
namespace {

namespace fb = tlvlink::wire;
using internal::string_list;
using internal::string_or_null;

Result<internal::SizeBound> hello_bound(const Hello& m) {
  constexpr const char* kWhat = "Hello";
  TLV_TRY(internal::check_list(kWhat, "sensors", m.sensors.size()));
  TLV_TRY(internal::check_list(kWhat, "heads", m.heads.size()));
  TLV_TRY(internal::check_list(kWhat, "stage_names", m.stage_names.size()));
  internal::SizeBound b;
  b.table(13);
  for (std::string_view s : {m.device, m.board, m.firmware_version, m.model_id, m.clock})
    b.string(s);
  b.vector(m.sensors.size(), 4);
  for (const SensorInfo& s : m.sensors) {
    b.table(8);
    for (std::string_view t : {s.name, s.model, s.serial, s.pixel_format}) b.string(t);
  }
  b.vector(m.heads.size(), 4);
  for (const HeadInfo& h : m.heads) {
    TLV_TRY(internal::check_list(kWhat, "a head's labels", h.labels.size()));
    b.table(5);
    b.string(h.name);
    b.vector(h.labels.size(), 4);
    for (std::string_view l : h.labels) b.string(l);
  }
  b.vector(m.stage_names.size(), 4);
  for (std::string_view s : m.stage_names) b.string(s);
  return b;
}

}  // namespace

Result<std::span<const std::byte>> encode_payload(const Hello& m, std::span<std::byte> buffer) {
  TLV_ASSIGN_OR_RETURN(const internal::SizeBound bound, hello_bound(m));
  return internal::build_payload("Hello", bound, buffer, [&](flatbuffers::FlatBufferBuilder& fbb) {
    std::array<flatbuffers::Offset<fb::SensorInfo>, kMaxListLength> sensors;
    for (size_t i = 0; i < m.sensors.size(); ++i) {
      const SensorInfo& s = m.sensors[i];
      const auto name = string_or_null(fbb, s.name), model = string_or_null(fbb, s.model),
                 serial = string_or_null(fbb, s.serial),
                 format = string_or_null(fbb, s.pixel_format);
      fb::SensorInfoBuilder sb(fbb);
      sb.add_index(s.index);
      sb.add_name(name);
      sb.add_model(model);
      sb.add_serial(serial);
      sb.add_pixel_format(format);
      sb.add_width(s.width);
      sb.add_height(s.height);
      sb.add_fps(s.fps);
      sensors[i] = sb.Finish();
    }
    std::array<flatbuffers::Offset<fb::HeadInfo>, kMaxListLength> heads;
    for (size_t i = 0; i < m.heads.size(); ++i) {
      const HeadInfo& h = m.heads[i];
      const auto name = string_or_null(fbb, h.name);
      const auto labels = string_list(fbb, h.labels);
      fb::HeadInfoBuilder hb(fbb);
      hb.add_name(name);
      hb.add_kind(static_cast<fb::HeadKind>(h.kind));
      hb.add_labels(labels);
      hb.add_accuracy(h.accuracy);
      hb.add_majority_rate(h.majority_rate);
      hb.add_accuracy_ci_low(h.accuracy_ci_low);
      hb.add_accuracy_ci_high(h.accuracy_ci_high);
      hb.add_balanced_accuracy(h.balanced_accuracy);
      hb.add_baseline_accuracy(h.baseline_accuracy);
      hb.add_groups(h.groups);
      heads[i] = hb.Finish();
    }
    const auto sensor_vec =
        m.sensors.empty() ? 0 : fbb.CreateVector(sensors.data(), m.sensors.size());
    const auto head_vec = m.heads.empty() ? 0 : fbb.CreateVector(heads.data(), m.heads.size());
    const auto stages = string_list(fbb, m.stage_names);
    const auto device = string_or_null(fbb, m.device), board = string_or_null(fbb, m.board),
               firmware = string_or_null(fbb, m.firmware_version),
               model_id = string_or_null(fbb, m.model_id), clock = string_or_null(fbb, m.clock);
    fb::HelloBuilder hb(fbb);
    hb.add_device(device);
    hb.add_board(board);
    hb.add_firmware_version(firmware);
    hb.add_boot_id(m.boot_id);
    hb.add_schema_hash(schema_hash());
    hb.add_model_id(model_id);
    hb.add_model_checksum(m.model_checksum);
    hb.add_sensors(sensor_vec);
    hb.add_heads(head_vec);
    hb.add_stage_names(stages);
    hb.add_embedding_dim(m.embedding_dim);
    hb.add_clock(clock);
    hb.add_max_frame_size(m.max_frame_size);
    return hb.Finish();
  });
}

}  // namespace tlvlink::protocol
