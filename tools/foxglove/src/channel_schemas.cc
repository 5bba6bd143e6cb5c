// JSON Schemas (draft 2020-12 keywords only: type, properties, items, required, description)
// of the listener's JSON lines. Every message shares the envelope (type ... send_host_ns,
// timestamp); each type adds its keys.
#include "channel_schemas.h"

#include <initializer_list>
#include <utility>

#include <nlohmann/json.hpp>

namespace tlvlink::foxglove::internal {
namespace {

using nlohmann::ordered_json;
using Props = std::initializer_list<std::pair<const char*, ordered_json>>;

ordered_json type(const char* t, const char* description = nullptr) {
  ordered_json j{{"type", t}};
  if (description) j["description"] = description;
  return j;
}
ordered_json integer(const char* d = nullptr) { return type("integer", d); }
ordered_json number(const char* d = nullptr) { return type("number", d); }
ordered_json nullable_number(const char* d) {
  return {{"type", {"number", "null"}}, {"description", d}};
}
ordered_json string(const char* d = nullptr) { return type("string", d); }
ordered_json boolean(const char* d = nullptr) { return type("boolean", d); }
// Enum values are names; a value this build does not know (a newer board) is its number.
ordered_json name_or_number(const char* d) {
  return {{"type", {"string", "integer"}}, {"description", d}};
}
ordered_json array(ordered_json items, const char* d = nullptr) {
  ordered_json j{{"type", "array"}, {"items", std::move(items)}};
  if (d) j["description"] = d;
  return j;
}
ordered_json object(Props props) {
  ordered_json p = ordered_json::object();
  for (const auto& [k, v] : props) p[k] = v;
  return {{"type", "object"}, {"properties", p}};
}

std::string message_schema(const char* title, Props props) {
  ordered_json j = {{"$schema", "https://json-schema.org/draft/2020-12/schema"},
                    {"title", title},
                    {"type", "object"}};
  ordered_json p = {
      {"type", string("message type (hello, frame_prediction, ...)")},
      {"sequence", integer("the board's frame sequence number")},
      {"flags", integer("frame header flags")},
      {"delayed", boolean("sent late by the board (queued while the link was busy)")},
      {"send_ns", integer("board clock, ns")},
      {"receive_ns", integer("host CLOCK_MONOTONIC when received, ns")},
      {"send_host_ns", integer("send_ns on the host clock (once the clock offset is known)")},
      {"timestamp", object({{"sec", integer()}, {"nsec", integer()}})},
  };
  for (const auto& [k, v] : props) p[k] = v;
  j["properties"] = p;
  j["required"] = {"type", "sequence", "send_ns", "receive_ns", "timestamp"};
  return j.dump();
}

ChannelSchemas build() {
  ChannelSchemas s;
  s.hello = message_schema(
      "tlvlink Hello: the board, its sensors and its heads",
      {{"device", string()},
       {"board", string()},
       {"firmware_version", string()},
       {"boot_id", string("16 hex digits")},
       {"schema_hash", string("16 hex digits")},
       {"schema_matches", boolean()},
       {"model_id", string()},
       {"model_checksum", string("hex")},
       {"sensors", array(object({{"index", integer()},
                                 {"name", string()},
                                 {"model", string()},
                                 {"serial", string()},
                                 {"pixel_format", string()},
                                 {"width", integer()},
                                 {"height", integer()},
                                 {"fps", number()}}))},
       {"heads", array(object({{"name", string()},
                               {"kind", name_or_number("head kind")},
                               {"labels", array(string())},
                               {"accuracy", nullable_number("NaN: null")},
                               {"majority_rate", nullable_number("NaN: null")},
                               {"accuracy_ci95", array(nullable_number("NaN: null"))},
                               {"balanced_accuracy", nullable_number("NaN: null")},
                               {"baseline_accuracy", nullable_number("NaN: null")},
                               {"groups", integer()}}))},
       {"stage_names", array(string())},
       {"embedding_dim", integer()},
       {"clock", string()},
       {"max_frame_size", integer()}});
  s.frame_prediction = message_schema(
      "tlvlink FramePrediction: one frame's contact flag and per-head probabilities",
      {{"sensor", integer()},
       {"sensor_name", string("from the Hello, if known")},
       {"frame_sequence", integer()},
       {"capture_ns", integer("board clock")},
       {"infer_start_ns", integer("board clock")},
       {"infer_end_ns", integer("board clock")},
       {"capture_host_ns", integer("capture_ns on the host clock")},
       {"stage_ns", array(integer(), "per-stage latency, ns (stage names in the Hello)")},
       {"contact", boolean()},
       {"gate", name_or_number("the contact gate: unknown (a board older than protocol 1.3), "
                               "calibrating, none, contact")},
       {"gate_score_dn", nullable_number("the gate's score, DN; null from a board older than 1.3")},
       {"heads", array(object({{"head", integer()},
                               {"name", string()},
                               {"probabilities", array(number())},
                               {"top_label", string()},
                               {"top_probability", number()}}))},
       {"embedding", array(number(), "if the board sends it")}});
  s.grasp_prediction = message_schema(
      "tlvlink GraspPrediction", {{"grasp_id", integer()},
                                  {"status", name_or_number("grasp status")},
                                  {"probability", nullable_number("null unless computed")},
                                  {"reason", name_or_number("grasp reason")},
                                  {"reason_text", string()},
                                  {"frames", array(object({{"sensor", integer()},
                                                           {"phase", name_or_number("grasp phase")},
                                                           {"frame_sequence", integer()},
                                                           {"capture_ns", integer()}}))},
                                  {"phase_source", name_or_number("phase source")},
                                  {"closed_ns", integer()},
                                  {"lifting_ns", integer()},
                                  {"infer_end_ns", integer()}});
  s.stats = message_schema("tlvlink Stats: fps, drops, CPU and link state, once a second",
                           {{"uptime_ns", integer()},
                            {"sensors", array(object({{"sensor", integer()},
                                                      {"fps", number()},
                                                      {"frames", integer()},
                                                      {"inferred", integer()},
                                                      {"gated", integer()}}))},
                            {"drops", array(object({{"cause", name_or_number("drop cause")},
                                                    {"count", integer()},
                                                    {"sensor", integer()}}))},
                            {"cpu_percent", nullable_number("NaN: null")},
                            {"cpu_cores", integer()},
                            {"rss_bytes", integer()},
                            {"link", object({{"link_up", boolean()},
                                             {"reconnects", integer()},
                                             {"frames_sent", integer()},
                                             {"bytes_sent", integer()},
                                             {"frames_received", integer()},
                                             {"frames_rejected", integer()},
                                             {"queue_messages", integer()},
                                             {"queue_bytes", integer()},
                                             {"queue_capacity_bytes", integer()}})}});
  s.error = message_schema(
      "tlvlink Error report",
      {{"code", integer()}, {"name", string()}, {"text", string()}, {"sensor", integer()}});
  s.ack =
      message_schema("tlvlink Ack of a host command",
                     {{"command_sequence", integer()}, {"kind", name_or_number("command kind")}});
  s.nack = message_schema("tlvlink Nack: a host command refused",
                          {{"command_sequence", integer()},
                           {"kind", name_or_number("command kind")},
                           {"code", integer()},
                           {"text", string()}});
  s.pong = message_schema("tlvlink Pong", {{"command_sequence", integer()},
                                           {"host_send_ns", integer()},
                                           {"board_receive_ns", integer()},
                                           {"round_trip_ns", integer()}});
  // Foxglove's own image schema (its keys: timestamp, frame_id, data, format), so its Image panel
  // shows the gel; the listener's other keys (contact, mask, ...) ride along for the Raw Messages
  // panel and plots.
  s.frame_image = message_schema(
      "foxglove.CompressedImage: a FrameImage of the board (tlvlink keys besides)",
      {{"frame_id", string("the sensor: its name from the Hello, else sensorN")},
       {"data", string("the JPEG, base64 (contentEncoding base64)")},
       {"format", string("\"jpeg\"")},
       {"sensor", integer()},
       {"sensor_name", string("from the Hello, if known")},
       {"frame_sequence", integer()},
       {"capture_ns", integer("board clock")},
       {"capture_host_ns", integer("capture_ns on the host clock")},
       {"kind", name_or_number("view (the decoded camera view) or input (the model's input)")},
       {"width", integer()},
       {"height", integer()},
       {"contact", boolean()},
       {"mask_width", integer("contact mask cells across")},
       {"mask_height", integer("cells down")},
       {"mask", array(string(),
                      "one string of 0/1 per row of cells: 1 = the cell differs from the "
                      "no-contact reference")}});
  return s;
}

}  // namespace

const ChannelSchemas& channel_schemas() {
  static const ChannelSchemas schemas = build();
  return schemas;
}

}  // namespace tlvlink::foxglove::internal
