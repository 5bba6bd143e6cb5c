// FramePrediction and GraspPrediction: the per-frame and per-grasp results.
#include <array>

#include "protocol_internal.h"

namespace tlvlink::protocol {
namespace {

namespace fb = tlvlink::wire;

static_assert(sizeof(GraspFrame) == sizeof(fb::GraspFrame), "GraspFrame mirrors the schema struct");

}  // namespace

Result<std::span<const std::byte>> encode_payload(const FramePrediction& m,
                                                  std::span<std::byte> buffer) {
  constexpr const char* kWhat = "FramePrediction";
  TLV_TRY(internal::check_list(kWhat, "heads", m.heads.size()));
  internal::SizeBound bound;
  bound.table(9);
  bound.bytes += sizeof(fb::FrameTiming);
  bound.vector(m.stage_ns.size(), 4);
  bound.vector(m.heads.size(), 4);
  for (const HeadOutput& h : m.heads) {
    bound.table(2);
    bound.vector(h.probabilities.size(), 4);
  }
  bound.vector(m.embedding.size(), 4);
  return internal::build_payload(kWhat, bound, buffer, [&](flatbuffers::FlatBufferBuilder& fbb) {
    std::array<flatbuffers::Offset<fb::HeadOutput>, kMaxListLength> heads;
    for (size_t i = 0; i < m.heads.size(); ++i) {
      const auto probabilities =
          fbb.CreateVector(m.heads[i].probabilities.data(), m.heads[i].probabilities.size());
      fb::HeadOutputBuilder hb(fbb);
      hb.add_head(m.heads[i].head);
      hb.add_probabilities(probabilities);
      heads[i] = hb.Finish();
    }
    flatbuffers::Offset<flatbuffers::Vector<flatbuffers::Offset<fb::HeadOutput>>> head_vec;
    if (!m.heads.empty()) head_vec = fbb.CreateVector(heads.data(), m.heads.size());
    flatbuffers::Offset<flatbuffers::Vector<uint32_t>> stages;
    if (!m.stage_ns.empty()) stages = fbb.CreateVector(m.stage_ns.data(), m.stage_ns.size());
    flatbuffers::Offset<flatbuffers::Vector<float>> embedding;
    if (!m.embedding.empty()) embedding = fbb.CreateVector(m.embedding.data(), m.embedding.size());
    const fb::FrameTiming timing(m.timing.capture_ns, m.timing.infer_start_ns,
                                 m.timing.infer_end_ns);
    fb::FramePredictionBuilder b(fbb);
    b.add_sensor(m.sensor);
    b.add_frame_sequence(m.frame_sequence);
    b.add_timing(&timing);
    b.add_stage_ns(stages);
    b.add_contact(m.contact);
    b.add_heads(head_vec);
    b.add_embedding(embedding);
    b.add_gate(static_cast<fb::GateState>(m.gate));
    b.add_gate_score_dn(m.gate_score_dn);
    return b.Finish();
  });
}

Result<std::span<const std::byte>> encode_payload(const GraspPrediction& m,
                                                  std::span<std::byte> buffer) {
  constexpr const char* kWhat = "GraspPrediction";
  TLV_TRY(internal::check_list(kWhat, "frames", m.frames.size()));
  internal::SizeBound bound;
  bound.table(10);
  bound.string(m.reason_text);
  bound.vector(m.frames.size(), sizeof(fb::GraspFrame));
  return internal::build_payload(kWhat, bound, buffer, [&](flatbuffers::FlatBufferBuilder& fbb) {
    std::array<fb::GraspFrame, kMaxListLength> frames;
    for (size_t i = 0; i < m.frames.size(); ++i) {
      const GraspFrame& f = m.frames[i];
      frames[i] = fb::GraspFrame(f.sensor, static_cast<fb::GraspPhase>(f.phase), f.frame_sequence,
                                 f.capture_ns);
    }
    flatbuffers::Offset<flatbuffers::Vector<const fb::GraspFrame*>> frame_vec;
    if (!m.frames.empty()) frame_vec = fbb.CreateVectorOfStructs(frames.data(), m.frames.size());
    const auto reason_text = internal::string_or_null(fbb, m.reason_text);
    fb::GraspPredictionBuilder b(fbb);
    b.add_grasp_id(m.grasp_id);
    b.add_status(static_cast<fb::GraspStatus>(m.status));
    // "Never a made-up value": a probability travels only with a computed prediction.
    if (m.status == GraspStatus::kComputed) b.add_probability(m.probability);
    b.add_reason(static_cast<fb::GraspReason>(m.reason));
    b.add_reason_text(reason_text);
    b.add_frames(frame_vec);
    b.add_phase_source(static_cast<fb::PhaseSource>(m.phase_source));
    b.add_closed_ns(m.closed_ns);
    b.add_lifting_ns(m.lifting_ns);
    b.add_infer_end_ns(m.infer_end_ns);
    return b.Finish();
  });
}

}  // namespace tlvlink::protocol
