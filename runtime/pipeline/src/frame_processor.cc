#include "tlvlink/pipeline/frame_processor.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string_view>

#include "tlvlink/clock.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::pipeline {
namespace {

// The reported heads: by name, or those heads::reported_by_default picks.
Result<std::vector<int16_t>> select_heads(const heads::HeadEvaluator& h,
                                          const std::vector<std::string>& names) {
  std::vector<int16_t> out;
  const auto results = h.results();
  if (names.empty()) {
    for (size_t i = 0; i < results.size(); ++i)
      if (heads::reported_by_default(results[i])) out.push_back(static_cast<int16_t>(i));
  }
  for (const std::string& name : names) {
    const auto it = std::find_if(results.begin(), results.end(), [&](const heads::HeadResult& r) {
      return r.name == name ||
             (std::string(heads::head_kind_name(r.kind)) + ":" + std::string(r.name)) == name;
    });
    if (it == results.end()) {
      std::string known;
      for (const heads::HeadResult& r : results)
        known += (known.empty() ? "" : ", ") + std::string(r.name) + " (" +
                 heads::head_kind_name(r.kind) + ")";
      if (h.has_grasp()) known += ", " + std::string(h.grasp_name()) + " (grasp)";
      return Error::make(ErrorCode::kInvalidArgument, "head '%s' is not in the model (it has: %s)",
                         name.c_str(), known.c_str());
    }
    out.push_back(static_cast<int16_t>(it - results.begin()));
  }
  TLV_ENSURE(out.size() <= static_cast<size_t>(kMaxHeads), ErrorCode::kInvalidArgument,
             "%zu heads selected; at most %d are reported per frame", out.size(), kMaxHeads);
  for (int16_t i : out) {
    const heads::HeadResult& r = results[static_cast<size_t>(i)];
    TLV_ENSURE(r.labels.size() <= static_cast<size_t>(kMaxLabels), ErrorCode::kModelUnsupported,
               "head '%.*s' has %zu labels; at most %d can be reported",
               static_cast<int>(r.name.size()), r.name.data(), r.labels.size(), kMaxLabels);
  }
  return out;
}

// Where the model's int8 part ends: the input of its last Dequantize, or the embedding output
// itself when that is int8; -1 when neither exists (a float model).
int32_t int8_end(const Graph& g, int32_t embedding_tensor) {
  if (g.tensor(embedding_tensor).dtype == DType::kInt8) return embedding_tensor;
  for (auto op = g.operators.rbegin(); op != g.operators.rend(); ++op)
    if (op->type == OpType::kDequantize) return op->inputs[0];
  return -1;
}

// report_embedding: both tensors fit a FramePrediction, and the int8 one is readable.
Result<int32_t> reported_int8_tensor(const Graph& g, const Executor& executor,
                                     int32_t embedding_tensor) {
  const size_t dim = g.tensor(embedding_tensor).shape.elements();
  TLV_ENSURE(dim <= static_cast<size_t>(kMaxReportedEmbedding), ErrorCode::kModelUnsupported,
             "report_embedding: the embedding has %zu values; at most %d can be reported", dim,
             kMaxReportedEmbedding);
  const int32_t q = int8_end(g, embedding_tensor);
  if (q < 0) return q;
  const Tensor& t = g.tensor(q);
  TLV_ENSURE(t.shape.elements() <= static_cast<size_t>(kMaxReportedInt8),
             ErrorCode::kModelUnsupported,
             "report_embedding: int8 tensor '%.*s' has %zu values; at most %d can be reported",
             static_cast<int>(t.name.size()), t.name.data(), t.shape.elements(), kMaxReportedInt8);
  auto bytes = executor.tensor(q);
  if (!bytes.ok()) return bytes.error().with_context("report_embedding");
  return q;
}

}  // namespace

Result<std::unique_ptr<FrameProcessor>> FrameProcessor::create(const Model& model,
                                                               Executor& executor,
                                                               std::span<const SensorSetup> sensors,
                                                               const ProcessorOptions& options) {
  TLV_ENSURE(!sensors.empty() && sensors.size() <= static_cast<size_t>(kMaxSensors),
             ErrorCode::kInvalidArgument, "%zu sensors (1..%d)", sensors.size(), kMaxSensors);
  auto p = std::unique_ptr<FrameProcessor>(new FrameProcessor(model, executor));
  p->options_ = options;
  const Graph& g = model.graph();
  TLV_ASSIGN_OR_RETURN(p->heads_, heads::HeadEvaluator::create(model.metadata()));
  TLV_ASSIGN_OR_RETURN(p->reported_, select_heads(p->heads_, options.heads));
  TLV_ASSIGN_OR_RETURN(const image::InputEncoding encoding,
                       image::input_encoding(g.tensor(g.inputs[0])));
  const int32_t out_index = std::max(model.metadata().embedding_output, 0);
  TLV_ENSURE(static_cast<size_t>(out_index) < g.outputs.size(), ErrorCode::kModelInvalidMetadata,
             "embedding output %d of %zu outputs", out_index, g.outputs.size());
  const Tensor& out = g.tensor(g.outputs[static_cast<size_t>(out_index)]);
  TLV_ENSURE(out.shape.elements() == static_cast<size_t>(model.metadata().embedding_dim),
             ErrorCode::kModelInvalidMetadata, "embedding output has %zu values, dim is %d",
             out.shape.elements(), model.metadata().embedding_dim);
  p->embedding_.assign(out.shape.elements(), 0.0f);
  if (options.report_embedding) {
    TLV_ASSIGN_OR_RETURN(
        p->int8_tensor_,
        reported_int8_tensor(g, executor, g.outputs[static_cast<size_t>(out_index)]));
  }
  int32_t fingers[2] = {-1, -1};
  for (size_t i = 0; i < sensors.size(); ++i) {
    const SensorSetup& s = sensors[i];
    auto plan = image::PreprocessPlan::create(model.metadata().input, s.width, s.height, s.channels,
                                              encoding);
    if (!plan.ok()) {
      return plan.error().with_context("sensor '%s' (%dx%dx%d frames) cannot feed the model",
                                       s.name.c_str(), s.width, s.height, s.channels);
    }
    auto gate = ContactGate::create(s.width, s.height, s.channels, options.contact);
    if (!gate.ok()) return gate.error().with_context("sensor '%s'", s.name.c_str());
    Sensor sensor{s,
                  std::move(gate).value(),
                  std::move(plan).value(),
                  {},
                  PressTracker(model.metadata().embedding_dim),
                  std::nullopt};
    for (int16_t h : p->reported_) {
      sensor.smoothers.emplace_back(
          static_cast<int32_t>(p->heads_.results()[static_cast<size_t>(h)].labels.size()),
          options.smoothing_tau_ns);
    }
    if (s.finger == 0 || s.finger == 1) {
      TLV_ENSURE(fingers[s.finger] < 0, ErrorCode::kInvalidArgument,
                 "sensors '%s' and '%s' are both finger %c",
                 sensors[static_cast<size_t>(fingers[s.finger])].name.c_str(), s.name.c_str(),
                 s.finger == 0 ? 'A' : 'B');
      fingers[s.finger] = static_cast<int32_t>(i);
    }
    p->sensors_.push_back(std::move(sensor));
  }
  if (options.grasp && p->heads_.has_grasp() && fingers[0] >= 0 && fingers[1] >= 0) {
    const InputSpec& input = model.metadata().input;
    TLV_ASSIGN_OR_RETURN(
        GraspTracker t,
        GraspTracker::create(p->heads_.grasp_layout(), model.metadata().embedding_dim,
                             options.grasp_options, {input.height, input.width, input.channels}));
    p->tracker_ = std::make_unique<GraspTracker>(std::move(t));
    const std::string& a = sensors[static_cast<size_t>(fingers[0])].sensor_model;
    if (a == sensors[static_cast<size_t>(fingers[1])].sensor_model)
      p->grasp_head_ = p->heads_.grasp_head_for(a);
    for (int32_t finger : {0, 1}) {
      if (!p->tracker_->wants_image(finger)) continue;
      Sensor& s = p->sensors_[static_cast<size_t>(fingers[finger])];
      auto plan = image::PreprocessPlan::create(heads::difference_input_spec(input), s.setup.width,
                                                s.setup.height, s.setup.channels);
      if (!plan.ok()) {
        return plan.error().with_context("sensor '%s': the grasp head's difference features",
                                         s.setup.name.c_str());
      }
      s.difference_plan = std::move(plan).value();
    }
    p->difference_image_.assign(p->tracker_->image_values(), 0.0f);  // 0 values without one
  }
  return p;
}

Status FrameProcessor::embed(Sensor& s, const image::ImageView& frame, FrameTimes& times) {
  TLV_TRY(s.plan.run(frame, executor_.input(0)));
  times.preprocessed_ns = board_clock_ns();
  // A frame from uint8 pixels through a plan whose every output is finite cannot hold NaN/Inf:
  // skip the input scan (it would cost a few percent of the encoder).
  TLV_TRY(s.plan.outputs_finite() ? executor_.invoke_trusted_inputs() : executor_.invoke());
  times.inferred_ns = board_clock_ns();
  const Graph& g = model_.graph();
  const auto o = static_cast<size_t>(std::max(model_.metadata().embedding_output, 0));
  const Tensor& t = g.tensor(g.outputs[o]);
  const std::span<const std::byte> bytes = executor_.output(o);
  if (t.dtype == DType::kFloat32) {
    std::memcpy(embedding_.data(), bytes.data(), embedding_.size() * sizeof(float));
  } else {
    for (size_t i = 0; i < embedding_.size(); ++i) {
      embedding_[i] =
          dequantize_value(static_cast<int8_t>(bytes[i]), t.quant.scale[0], t.quant.zero_point[0]);
    }
  }
  return heads_.evaluate(embedding_);
}

Status FrameProcessor::process(int32_t index, uint64_t sequence, const image::ImageView& frame,
                               const FrameTimes& in_times, FramePrediction& out) {
  TLV_ENSURE(index >= 0 && static_cast<size_t>(index) < sensors_.size(),
             ErrorCode::kInvalidArgument, "sensor %d of %zu", index, sensors_.size());
  Sensor& s = sensors_[static_cast<size_t>(index)];
  out = FramePrediction{};
  out.sensor = index;
  out.sequence = sequence;
  out.times = in_times;
  ++counters_.frames;
  ++counters_.sensor_frames[static_cast<size_t>(index)];
  auto decision = s.gate.update(frame);
  if (!decision.ok()) return decision.error().with_context("sensor '%s'", s.setup.name.c_str());
  out.times.gated_ns = board_clock_ns();
  out.contact_state = static_cast<uint8_t>(decision->state);
  out.contact_score_dn = decision->score_dn;
  const bool contact = decision->state != ContactState::kNoContact;
  const int32_t finger = s.setup.finger;
  const bool wanted =
      tracker_ != nullptr && finger >= 0 && tracker_->wants(finger, in_times.capture_ns);
  const bool run = !options_.contact_gating || contact || wanted;
  if (decision->onset) {
    for (ProbabilitySmoother& sm : s.smoothers) sm.restart();
    s.press.restart();
  }
  std::span<const float> embedding;
  if (run) {
    if (Status st = embed(s, frame, out.times); !st.ok())
      return st.error().with_context("sensor '%s' frame %llu", s.setup.name.c_str(),
                                     static_cast<unsigned long long>(sequence));
    out.times.heads_ns = board_clock_ns();
    ++counters_.encoder_runs;
    ++counters_.sensor_encoder_runs[static_cast<size_t>(index)];
    counters_.grasp_forced += (!contact && wanted) ? 1 : 0;
    embedding = embedding_;
    out.encoder_ran = true;
    if (options_.report_embedding) report(out);
  }
  // Predictions are reported in contact only: a frame encoded for the grasp tracker's open-gel
  // "before" moment says nothing about a material.
  if (run && (contact || !options_.contact_gating)) {
    const bool held = decision->state == ContactState::kContact;
    if (Status st = report_heads(s, held, decision->score_dn, in_times.capture_ns, out); !st.ok())
      return st.error().with_context("sensor '%s' frame %llu: press heads", s.setup.name.c_str(),
                                     static_cast<unsigned long long>(sequence));
  }
  if (!run) {
    ++counters_.gated;
    ++counters_.sensor_gated[static_cast<size_t>(index)];
  }
  if (tracker_ != nullptr && finger >= 0) {
    // The tracker's contact is the gate's (calibrating counts as no contact: no grasp before the
    // reference exists).
    const bool held = decision->state == ContactState::kContact;
    std::span<const float> image;
    // The frames the tracker may keep for a difference: an open gel, or a moment it asked for.
    if (run && s.difference_plan && (wanted || !held)) {
      if (Status st = s.difference_plan->run(frame, difference_image_); !st.ok())
        return st.error().with_context("sensor '%s' frame %llu: grasp difference image",
                                       s.setup.name.c_str(),
                                       static_cast<unsigned long long>(sequence));
      image = difference_image_;
    }
    tracker_->on_frame(finger, sequence, in_times.capture_ns, held, embedding, image);
  }
  return {};
}

Status FrameProcessor::report_heads(Sensor& s, bool held, float score_dn, int64_t capture_ns,
                                    FramePrediction& out) {
  bool press_ready = false;
  if (held && heads_.has_press()) {
    s.press.add(embedding_, score_dn);
    press_ready = s.press.ready();
    if (press_ready) TLV_TRY(heads_.evaluate_press(s.press.peak(), s.press.first()));
  }
  const auto results = heads_.results();
  int32_t n = 0;
  for (size_t k = 0; k < reported_.size(); ++k) {
    const heads::HeadResult& r = results[static_cast<size_t>(reported_[k])];
    const bool press = r.kind == heads::HeadKind::kPress;
    if (press && !press_ready) continue;  // the head has not answered on this contact yet
    HeadProbabilities& h = out.heads[static_cast<size_t>(n++)];
    h.head = reported_[k];
    h.labels = static_cast<int16_t>(r.labels.size());
    const std::span<float> p(h.probability.data(), r.labels.size());
    if (press) {
      std::copy(r.probabilities.begin(), r.probabilities.end(), p.begin());
    } else {
      s.smoothers[k].add(r.probabilities, capture_ns, p);
    }
    h.top = static_cast<int16_t>(std::max_element(p.begin(), p.end()) - p.begin());
  }
  out.head_count = n;
  return {};
}

void FrameProcessor::report(FramePrediction& out) const {
  out.embedding_dim = static_cast<int32_t>(embedding_.size());
  std::copy(embedding_.begin(), embedding_.end(), out.embedding.begin());
  if (int8_tensor_ < 0) return;
  const auto bytes = executor_.tensor(int8_tensor_);  // checked readable at create()
  if (!bytes.ok()) return;
  out.int8_count = static_cast<int32_t>(bytes->size());
  std::memcpy(out.int8_values.data(), bytes->data(), bytes->size());
}

bool FrameProcessor::take_grasp(GraspPrediction& out) {
  if (tracker_ == nullptr) return false;
  std::span<const float> features[kMaxGraspFeatures];
  if (!tracker_->take_finished(out, features)) return false;
  if (out.computed) {
    auto p = heads_.grasp_probability(
        std::span<const std::span<const float>>(features, static_cast<size_t>(out.feature_count)),
        grasp_head_);
    if (p.ok()) {
      out.probability = *p;
    } else {
      out.computed = false;
      std::snprintf(out.reason.data(), out.reason.size(), "%s", p.error().message());
    }
  }
  (out.computed ? counters_.grasps_computed : counters_.grasps_not_computed) += 1;
  return true;
}

void FrameProcessor::tick(int64_t now_ns) {
  if (tracker_ != nullptr) tracker_->tick(now_ns);
}

void FrameProcessor::rezero(int32_t sensor) {
  for (size_t i = 0; i < sensors_.size(); ++i)
    if (sensor < 0 || static_cast<size_t>(sensor) == i) sensors_[i].gate.rezero();
}

bool FrameProcessor::mark_closed(int64_t t_ns) {
  return tracker_ != nullptr && tracker_->mark_closed(t_ns);
}

bool FrameProcessor::mark_lifting(int64_t t_ns) {
  return tracker_ != nullptr && tracker_->mark_lifting(t_ns);
}

}  // namespace tlvlink::pipeline
