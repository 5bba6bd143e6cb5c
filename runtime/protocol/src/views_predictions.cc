#include "protocol_internal.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::protocol {
namespace {

namespace fb = tlvlink::wire;

const fb::FramePrediction* frame(const void* t) {
  return static_cast<const fb::FramePrediction*>(t);
}
const fb::GraspPrediction* grasp(const void* t) {
  return static_cast<const fb::GraspPrediction*>(t);
}

// Scalar vectors are little-endian on the wire and 4-byte aligned in a verified buffer: on a
// little-endian machine they are read in place.
static_assert(FLATBUFFERS_LITTLEENDIAN,
              "tlvlink reads scalar vectors in place (little-endian only)");
template <typename T>
std::span<const T> span_of(const flatbuffers::Vector<T>* v) {
  return v ? std::span<const T>(v->data(), v->size()) : std::span<const T>();
}

}  // namespace

uint8_t FramePredictionView::sensor() const { return frame(table_)->sensor(); }
uint32_t FramePredictionView::frame_sequence() const { return frame(table_)->frame_sequence(); }
FrameTiming FramePredictionView::timing() const {
  FrameTiming t;
  if (const fb::FrameTiming* f = frame(table_)->timing()) {
    t.capture_ns = f->capture_ns();
    t.infer_start_ns = f->infer_start_ns();
    t.infer_end_ns = f->infer_end_ns();
  }
  return t;
}
std::span<const uint32_t> FramePredictionView::stage_ns() const {
  return span_of(frame(table_)->stage_ns());
}
bool FramePredictionView::contact() const { return frame(table_)->contact(); }
size_t FramePredictionView::head_count() const {
  const auto* heads = frame(table_)->heads();
  return heads ? heads->size() : 0;
}
HeadOutput FramePredictionView::head(size_t i) const {
  const fb::HeadOutput* h = frame(table_)->heads()->Get(static_cast<flatbuffers::uoffset_t>(i));
  return HeadOutput{h->head(), span_of(h->probabilities())};
}
std::span<const float> FramePredictionView::embedding() const {
  return span_of(frame(table_)->embedding());
}
GateState FramePredictionView::gate() const {
  return static_cast<GateState>(frame(table_)->gate());
}
float FramePredictionView::gate_score_dn() const { return frame(table_)->gate_score_dn(); }

uint32_t GraspPredictionView::grasp_id() const { return grasp(table_)->grasp_id(); }
GraspStatus GraspPredictionView::status() const {
  return static_cast<GraspStatus>(grasp(table_)->status());
}
float GraspPredictionView::probability() const { return grasp(table_)->probability(); }
GraspReason GraspPredictionView::reason() const {
  return static_cast<GraspReason>(grasp(table_)->reason());
}
std::string_view GraspPredictionView::reason_text() const {
  return internal::view(grasp(table_)->reason_text());
}
size_t GraspPredictionView::frame_count() const {
  const auto* frames = grasp(table_)->frames();
  return frames ? frames->size() : 0;
}
GraspFrame GraspPredictionView::frame(size_t i) const {
  const fb::GraspFrame* f = grasp(table_)->frames()->Get(static_cast<flatbuffers::uoffset_t>(i));
  return GraspFrame{f->sensor(), static_cast<GraspPhase>(f->phase()), f->frame_sequence(),
                    f->capture_ns()};
}
PhaseSource GraspPredictionView::phase_source() const {
  return static_cast<PhaseSource>(grasp(table_)->phase_source());
}
int64_t GraspPredictionView::closed_ns() const { return grasp(table_)->closed_ns(); }
int64_t GraspPredictionView::lifting_ns() const { return grasp(table_)->lifting_ns(); }
int64_t GraspPredictionView::infer_end_ns() const { return grasp(table_)->infer_end_ns(); }

Result<FramePredictionView> decode_frame_prediction(std::span<const std::byte> payload) {
  TLV_ASSIGN_OR_RETURN(const fb::FramePrediction* root,
                       internal::verified_root<fb::FramePrediction>("FramePrediction", payload));
  return FramePredictionView(root);
}

Result<GraspPredictionView> decode_grasp_prediction(std::span<const std::byte> payload) {
  TLV_ASSIGN_OR_RETURN(const fb::GraspPrediction* root,
                       internal::verified_root<fb::GraspPrediction>("GraspPrediction", payload));
  return GraspPredictionView(root);
}

}  // namespace tlvlink::protocol
