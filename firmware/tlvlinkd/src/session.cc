#include "tlvlink/daemon/session.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <thread>

#include "board_hello.h"
#include "capture_worker.h"
#include "clock.h"
#include "commands.h"
#include "inference_worker.h"
#include "jsonl_sink.h"
#include "jsonl_writer.h"
#include "output_worker.h"
#if defined(TLVLINK_HAVE_STREAM)
#include "stream_sink.h"
#endif
#include "sources.h"
#include "tlvlink/capture/sensor_models.h"
#include "tlvlink/daemon/model_check.h"
#include "tlvlink/executor.h"
#include "tlvlink/head_trust.h"
#include "tlvlink/log.h"
#include "tlvlink/model.h"
#include "tlvlink/pipeline/frame_processor.h"
#include "tlvlink/stream/names.h"
#include "tlvlink/verify/golden.h"

namespace tlvlink::daemon {

TLV_LOG_CATEGORY(kLogDaemon, "daemon");

struct Session::Impl {
  DaemonConfig config;
  std::unique_ptr<Model> model;
  std::unique_ptr<Executor> executor;
  std::unique_ptr<pipeline::FrameProcessor> processor;
  internal::Doorbell doorbell;
  std::vector<std::unique_ptr<internal::FrameRing>> rings;
  std::unique_ptr<internal::OutputQueue> queue;
  internal::CommandQueue commands;
  internal::OutputNames names;
  std::vector<std::unique_ptr<internal::OutputSink>> sinks;
  std::vector<std::unique_ptr<internal::CaptureWorker>> captures;
  std::unique_ptr<internal::FrameImages> images;  // frame_images on: the JPEG encoder thread's
  std::unique_ptr<internal::InferenceWorker> inference;
  std::unique_ptr<internal::OutputWorker> output;
  std::atomic<bool> capture_stop{false}, inference_stop{false}, output_stop{false},
      images_stop{false};
  std::atomic<bool> limit{false};
  std::vector<std::thread> capture_threads;
  std::thread inference_thread, output_thread, images_thread;
  bool stopped = false;
  SessionTotals totals;
};

namespace {

Result<std::unique_ptr<Executor>> make(const Model& m, const DaemonConfig& c) {
  TLV_ASSIGN_OR_RETURN(const ExecutorKind kind, parse_executor_kind(c.executor));
  ExecutorOptions o;
  o.threads = c.threads;
  o.expose_all_tensors = c.processing.report_embedding;  // the int8 tensor it reports
  return make_executor(m, kind, o);
}

// A replay not paced to the camera's clock: nothing is lost by making it wait for the
// consumer, so every one of its frames (and, when all sources are such, every record) is kept.
bool read_at_speed(const SensorConfig& c) { return c.source == SourceKind::kReplay && !c.realtime; }

// One log line per head at start: whether it is reported and the trust record that decides it,
// so a user who fitted a head (`tlvlink heads fit --images`) sees the daemon take it up.
void log_heads(const pipeline::FrameProcessor& p) {
  const auto& results = p.heads().results();
  for (size_t i = 0; i < results.size(); ++i) {
    const heads::HeadResult& r = results[i];
    bool reported = false;
    for (int16_t k : p.reported_heads()) reported |= static_cast<size_t>(k) == i;
    char record[256] = "no trust record";
    if (r.trust != nullptr && r.trust->present) {
      const HeadTrust& t = *r.trust;
      const TrustAssessment a = assess_head(t);
      int n =
          std::snprintf(record, sizeof record, "%s: accuracy %.1f %% vs majority %.1f %% (n=%lld)",
                        head_trust_level_name(a.level), 100.0 * static_cast<double>(t.accuracy),
                        100.0 * static_cast<double>(t.majority), static_cast<long long>(t.n));
      if (t.ci_low >= 0 && n > 0 && static_cast<size_t>(n) < sizeof record) {
        n += std::snprintf(record + n, sizeof record - static_cast<size_t>(n),
                           ", cross-validated over %lld groups, 95 %% CI [%.1f, %.1f]",
                           static_cast<long long>(t.groups), 100.0 * static_cast<double>(t.ci_low),
                           100.0 * static_cast<double>(t.ci_high));
      }
      if (t.baseline_accuracy >= 0 && n > 0 && static_cast<size_t>(n) < sizeof record) {
        std::snprintf(record + n, sizeof record - static_cast<size_t>(n), ", baseline %.1f %%%s",
                      100.0 * static_cast<double>(t.baseline_accuracy),
                      a.below_baseline ? " (not beaten)" : "");
      }
    }
    TLV_LOG(kLogDaemon, kInfo, "head %.*s (%s): %s; %s", static_cast<int>(r.name.size()),
            r.name.data(), heads::head_kind_name(r.kind), reported ? "reported" : "not reported",
            record);
  }
  if (!p.tracks_grasps()) return;
  // Which grasp head the fingers' sensor model picked (the model may hold one per model).
  TLV_LOG(kLogDaemon, kInfo, "grasp head %s; %zu in the model",
          heads::grasp_head_label(p.heads(), p.grasp_head()).c_str(), p.heads().grasp_head_count());
}

}  // namespace

Session::Session(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Session::~Session() { stop(); }

Result<std::unique_ptr<Session>> Session::start(const DaemonConfig& config) {
  TLV_ASSIGN_OR_RETURN(auto sources, internal::make_sources(config));
  return start_with_sources(config, std::move(sources));
}

Result<std::unique_ptr<Session>> Session::start_with_sources(
    const DaemonConfig& config, std::vector<std::unique_ptr<capture::FrameSource>> sources) {
  TLV_ENSURE(sources.size() == config.sensors.size(), ErrorCode::kInvalidArgument,
             "%zu sources for %zu sensors", sources.size(), config.sensors.size());
  auto impl = std::make_unique<Impl>();
  Impl& s = *impl;
  s.config = config;
  TLV_ASSIGN_OR_RETURN(s.model, load_config_model(config));
  TLV_ASSIGN_OR_RETURN(s.executor, make(*s.model, config));
  if (config.verify_model) {
    // The start-up self-test: the model's golden pairs on this board's executor.
    auto report = verify::verify_golden(*s.model, *s.executor);
    if (!report.ok()) return report.error().with_context("verifying %s", config.model.c_str());
    TLV_ENSURE(report->heads.pass, ErrorCode::kModelChecksum,
               "%s: golden head outputs do not match (max error %.4g > %.4g)", config.model.c_str(),
               report->heads.max_abs_error, report->heads.tolerance);
    TLV_ENSURE(report->pass, ErrorCode::kModelChecksum,
               "%s: golden pairs do not match on the %s executor (max error %.4g > %.4g)",
               config.model.c_str(), executor_kind_name(s.executor->kind()),
               report->pairs.back().comparison.max_abs_error,
               report->pairs.back().comparison.tolerance);
  }
  std::vector<pipeline::SensorSetup> setups;
  for (const SensorConfig& c : config.sensors) {
    setups.push_back({c.name, c.view.width, c.view.height, 3, c.finger, c.sensor_model});
  }
  TLV_ASSIGN_OR_RETURN(s.processor, pipeline::FrameProcessor::create(*s.model, *s.executor, setups,
                                                                     config.processing));
  s.queue = std::make_unique<internal::OutputQueue>(
      config.output_queue,
      std::all_of(config.sensors.begin(), config.sensors.end(), read_at_speed));
  std::vector<std::string> sensor_names;
  for (const SensorConfig& c : config.sensors) sensor_names.push_back(c.name);
  s.names = stream::output_names(std::move(sensor_names), s.processor->heads(),
                                 s.processor->grasp_head());
#if defined(TLVLINK_HAVE_STREAM)
  internal::StreamSink* link = nullptr;
#endif
  for (const std::string& o : config.outputs) {
    if (o.rfind("jsonl:", 0) == 0) {
      TLV_ASSIGN_OR_RETURN(internal::JsonlWriter writer, internal::JsonlWriter::open(o.substr(6)));
      s.sinks.push_back(std::make_unique<internal::JsonlSink>(
          std::move(writer), internal::make_hello(config, *s.model, s.names),
          config.processing.grasp_options.mode == pipeline::GraspOptions::Mode::kDetected));
      continue;
    }
#if defined(TLVLINK_HAVE_STREAM)
    TLV_ASSIGN_OR_RETURN(auto stream,
                         internal::StreamSink::open(o, config, *s.model, s.names, s.commands));
    link = stream.get();  // at most one (config.cc)
    s.sinks.push_back(std::move(stream));
#else
    return Error::make(ErrorCode::kInvalidArgument,
                       "output '%s': this tlvlinkd was built without the stream link "
                       "(TLVLINK_WITH_SERIAL=OFF)",
                       o.c_str());
#endif
  }
#if defined(TLVLINK_HAVE_STREAM)
  if (config.frame_images != FrameImageKind::kOff) {
    TLV_ENSURE(link != nullptr, ErrorCode::kInvalidArgument, "frame_images: no stream output");
    TLV_ASSIGN_OR_RETURN(
        s.images, internal::FrameImages::create(
                      config, setups, *s.processor,
                      [link](const stream::FrameImageRecord& r) { return link->post_image(r); }));
  }
#endif
  std::vector<internal::OutputSink*> sinks;
  for (auto& sink : s.sinks) sinks.push_back(sink.get());
  std::vector<internal::FrameRing*> rings;
  for (size_t i = 0; i < config.sensors.size(); ++i) {
    const SensorConfig& c = config.sensors[i];
    // The decoder for what the source negotiated (it may differ from the configured size when
    // accept_other_size is set).
    const image::FrameFormat& format =
        sources[i]->stats().connected ? sources[i]->format() : c.format;
    auto decoder = image::FrameDecoder::create(format, c.view);
    if (!decoder.ok()) return decoder.error().with_context("sensor '%s'", c.name.c_str());
    s.rings.push_back(std::make_unique<internal::FrameRing>(
        config.queue_frames, decoder->output_bytes(), s.doorbell,
        read_at_speed(c) ? internal::WhenFull::kWaitForConsumer : internal::WhenFull::kDropOldest));
    rings.push_back(s.rings.back().get());
    s.captures.push_back(std::make_unique<internal::CaptureWorker>(
        static_cast<int32_t>(i), c.name, std::move(sources[i]), std::move(decoder).value(),
        *s.rings.back(), *s.queue, s.capture_stop));
  }
  std::vector<internal::ScriptedCommand> script;
  if (!config.command_script.empty()) {
    int32_t sensor_of_finger[2] = {-1, -1};
    for (size_t i = 0; i < config.sensors.size(); ++i) {
      const int32_t finger = config.sensors[i].finger;
      if (finger == 0 || finger == 1) sensor_of_finger[finger] = static_cast<int32_t>(i);
    }
    TLV_ASSIGN_OR_RETURN(script,
                         internal::load_command_script(config.command_script, sensor_of_finger));
  }
  s.inference = std::make_unique<internal::InferenceWorker>(
      *s.processor, rings, setups, s.doorbell, *s.queue, s.commands, s.inference_stop, s.limit,
      config.max_frames, std::move(script));
  s.output = std::make_unique<internal::OutputWorker>(
      sinks, s.names, *s.queue, s.captures, *s.inference, rings, config.status_interval_ms,
      config.status_line, s.output_stop);
  s.inference->set_frame_images(s.images.get());
  s.output->set_frame_images(s.images.get());
  if (s.images) s.images_thread = std::thread([&s] { s.images->run(s.images_stop); });
  s.output_thread = std::thread([&s] { s.output->run(); });
  s.inference_thread = std::thread([&s] { s.inference->run(); });
  for (auto& c : s.captures) s.capture_threads.emplace_back([w = c.get()] { w->run(); });
  log_heads(*s.processor);
  TLV_LOG(kLogDaemon, kInfo, "streaming %zu sensor(s) into %s (%s executor, %d thread(s))",
          config.sensors.size(), config.model.c_str(), executor_kind_name(s.executor->kind()),
          config.threads);
  return std::unique_ptr<Session>(new Session(std::move(impl)));
}

bool Session::limit_reached() const {
  if (impl_->limit.load() || impl_->output->outputs_closed()) return true;
  // Every source is a replay that played its last frame: the session has nothing more to do.
  for (const auto& c : impl_->captures)
    if (!c->ended()) return false;
  return !impl_->captures.empty();
}

uint64_t Session::frames_processed() const { return impl_->inference->snapshot().counters.frames; }

bool Session::command(std::string_view line) {
  internal::Command c;
  if (!internal::parse_command(line, board_clock_ns(), c)) return false;
  return impl_->commands.push(c);
}

SessionTotals Session::stop() {
  Impl& s = *impl_;
  if (s.stopped) return s.totals;
  s.stopped = true;
  // Capture first; then every frame already decoded is processed; then every record written.
  s.capture_stop = true;
  for (std::thread& t : s.capture_threads) t.join();
  s.inference_stop = true;
  s.inference_thread.join();
  s.images_stop = true;
  if (s.images_thread.joinable()) s.images_thread.join();
  s.output_stop = true;
  s.queue->close();
  s.output_thread.join();
  s.output->print_summary(stderr);
  const internal::RunTotals r = s.output->totals();
  s.totals = {r.frames,
              r.encoded,
              r.gated,
              r.grasps,
              r.grasps_not_computed,
              r.drops_stale,
              r.drops_sequence,
              r.drops_queue,
              r.drops_output,
              r.bad_frames,
              r.decode_errors,
              r.inference_errors,
              r.write_errors,
              0,
              r.seconds,
              r.p50_ms[internal::kTotal],
              r.p99_ms[internal::kTotal],
              r.peak_rss_kb};
  for (const auto& c : s.captures) s.totals.failed_sources += c->failed() ? 1 : 0;
  s.totals.images_sent = r.images_sent;
  s.totals.images_busy = r.drops_image;
  return s.totals;
}

}  // namespace tlvlink::daemon
