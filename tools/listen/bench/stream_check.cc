// tlvlink_stream_check: the stream end to end over any link, in two processes (or two machines,
// or the emulated board and its USB host side):
//   tlvlink_stream_check board --link LINK [--frames N] [--rate HZ] [--embedding] [--hold S] [--boot-id N]
//       a board: the Sender on LINK (make_transport: serial:PATH, pty:LINK, usb[:FFS_DIR,...])
//       posting N fixture predictions at HZ (every 10th frame also a grasp), Stats every second,
//       answering commands (set bad=... is refused); then holds the link S seconds and flushes.
//   tlvlink_stream_check check --source SOURCE [--frames N] [--timeout S]
//       a host: the Client on SOURCE (serial:PATH, usb[:VID:PID][,serial=S]); sends ping, info,
//       start, closed 1, set bad=1; expects every prediction 0..N-1 intact and in order and each
//       command answered (the last refused). Prints what it got; exit 0 when all is well.
//   tlvlink_stream_check record FILE [--cut]
//       writes the deterministic fixture recording (fixture_recording.h).
// In this repository it runs over a pty (tests/listen); in the emulated board over CDC-ACM and
// the FunctionFS gadget through dummy_hcd (tools/rig).

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <set>
#include <string>
#include <thread>

#include "fixture_recording.h"
#include "tlvlink/listen/client.h"
#include "tlvlink/listen/command_text.h"
#include "tlvlink/protocol/names.h"
#include "tlvlink/transport/sender.h"
#include "tlvlink/transport/time.h"
#include "tlvlink/transport/transport_spec.h"
#include "transport/stream_fixture.h"

namespace {

using namespace tlvlink;
using transport::monotonic_ns;

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop = true; }

struct Args {
  std::string mode, link, source, file;
  uint32_t frames = 100;
  double rate = 120, hold_s = 1, timeout_s = 30;
  uint64_t boot_id = 0x5EED;
  bool embedding = false, cut = false;
};

bool parse(int argc, char** argv, Args& a) {
  if (argc < 2) return false;
  a.mode = argv[1];
  for (int i = 2; i < argc; ++i) {
    const std::string k = argv[i];
    auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : ""; };
    if (k == "--link") a.link = value();
    else if (k == "--source") a.source = value();
    else if (k == "--frames") a.frames = static_cast<uint32_t>(std::strtoul(value(), nullptr, 10));
    else if (k == "--rate") a.rate = std::strtod(value(), nullptr);
    else if (k == "--hold") a.hold_s = std::strtod(value(), nullptr);
    else if (k == "--timeout") a.timeout_s = std::strtod(value(), nullptr);
    else if (k == "--embedding") a.embedding = true;
    else if (k == "--boot-id") a.boot_id = std::strtoull(value(), nullptr, 0);
    else if (k == "--cut") a.cut = true;
    else if (a.mode == "record" && a.file.empty()) a.file = k;
    else return false;
  }
  return true;
}

int board(const Args& a) {
  Result<std::unique_ptr<transport::Transport>> link = transport::make_transport(a.link);
  if (!link.ok()) return std::fprintf(stderr, "board: %s\n", link.error().message()), 2;
  Result<std::unique_ptr<transport::Sender>> s = transport::Sender::create(std::move(link.value()), {});
  if (!s.ok()) return std::fprintf(stderr, "board: %s\n", s.error().message()), 2;
  transport::Sender& sender = *s.value();
  protocol::Hello hello = testing::fixture_hello();
  hello.boot_id = a.boot_id;
  (void)sender.set_hello(hello);
  (void)sender.set_command_handler([](const protocol::Command& c) -> Status {
    if (c.kind == protocol::CommandKind::kSetConfig && c.key == "bad") {
      return Error(ErrorCode::kInvalidArgument, "unknown key 'bad'");
    }
    return Status();
  });
  (void)sender.start();
  std::printf("board: ready on %s\n", a.link.c_str());
  std::fflush(stdout);
  const int64_t period = static_cast<int64_t>(1e9 / a.rate);
  int64_t next = monotonic_ns(), next_stats = next + 1'000'000'000;
  testing::PredictionStorage st;
  for (uint32_t n = 0; n < a.frames && !g_stop; ++n) {
    (void)sender.post(testing::fixture_prediction(n, st, a.embedding, monotonic_ns()));
    if (n % 10 == 9) {
      protocol::GraspPrediction g;
      g.grasp_id = n / 10;
      g.status = (n / 10) % 2 ? protocol::GraspStatus::kNotComputed : protocol::GraspStatus::kComputed;
      g.probability = 0.75f;
      g.reason = (n / 10) % 2 ? protocol::GraspReason::kLateFinger : protocol::GraspReason::kNone;
      g.infer_end_ns = monotonic_ns();
      (void)sender.post(g);
    }
    if (monotonic_ns() >= next_stats) {
      (void)sender.post(protocol::Stats{});
      next_stats += 1'000'000'000;
    }
    next += period;
    const int64_t wait = next - monotonic_ns();
    if (wait > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
  }
  for (int64_t end = monotonic_ns() + static_cast<int64_t>(a.hold_s * 1e9); monotonic_ns() < end && !g_stop;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  (void)sender.post(protocol::Stats{});
  sender.stop();
  const transport::SenderCounters c = sender.counters();
  std::printf("board: posted %llu, sent %llu frames (%llu bytes, %llu delayed), dropped %llu queue_full %llu link_down, "
              "%u reconnects, %llu commands (%llu refused)\n",
              static_cast<unsigned long long>(c.posted), static_cast<unsigned long long>(c.frames_sent),
              static_cast<unsigned long long>(c.bytes_sent), static_cast<unsigned long long>(c.delayed_sent),
              static_cast<unsigned long long>(c.dropped_queue_full), static_cast<unsigned long long>(c.dropped_link_down),
              c.reconnects, static_cast<unsigned long long>(c.commands), static_cast<unsigned long long>(c.commands_refused));
  return 0;
}

int check(const Args& a) {
  Result<std::unique_ptr<listen::Client>> c = listen::Client::open(a.source);
  if (!c.ok()) return std::fprintf(stderr, "check: %s\n", c.error().message()), 2;
  listen::Client& client = *c.value();
  const char* commands[] = {"ping", "info", "start", "closed 1", "set bad=1"};
  std::set<uint32_t> awaiting;
  uint32_t refused_seq = 0;
  bool sent = false, refused_ok = false;
  uint32_t next_frame = 0, out_of_order = 0, corrupted = 0, grasps = 0, acks = 0, pongs = 0;
  const int64_t start = monotonic_ns(), deadline = start + static_cast<int64_t>(a.timeout_s * 1e9);
  int64_t first = 0, last = 0;
  while (!g_stop && monotonic_ns() < deadline && (next_frame < a.frames || !awaiting.empty() || !sent)) {
    Result<std::optional<listen::Message>> m = client.next(100);
    for (const listen::LinkEvent& e : client.take_events()) {
      std::printf("check: %s: %s\n", listen::link_event_name(e.kind), e.text.c_str());
    }
    if (!m.ok()) return std::fprintf(stderr, "check: %s\n", m.error().message()), 1;
    if (!m.value()) continue;
    const listen::Message& msg = *m.value();
    if (msg.type() == protocol::MessageType::kHello && !sent) {
      for (const char* text : commands) {
        Result<uint32_t> seq = client.send(listen::parse_command(text).value());
        if (!seq.ok()) return std::fprintf(stderr, "check: sending '%s': %s\n", text, seq.error().message()), 1;
        awaiting.insert(seq.value());
        if (std::strncmp(text, "set bad", 7) == 0) refused_seq = seq.value();
      }
      sent = true;
    }
    if (auto f = msg.frame_prediction(); f.ok()) {
      if (!testing::fixture_prediction_intact(f.value())) ++corrupted;
      if (f.value().frame_sequence() != next_frame) ++out_of_order;
      next_frame = f.value().frame_sequence() + 1;
      if (first == 0) first = msg.receive_ns();
      last = msg.receive_ns();
    }
    if (msg.grasp_prediction().ok()) ++grasps;
    if (auto p = msg.pong(); p.ok()) awaiting.erase(p.value().command_sequence), ++pongs;
    if (auto k = msg.ack(); k.ok()) awaiting.erase(k.value().command_sequence), ++acks;
    if (auto n = msg.nack(); n.ok()) {
      awaiting.erase(n.value().command_sequence);
      refused_ok = n.value().command_sequence == refused_seq;
    }
  }
  const listen::LinkStats s = client.stats();
  const double seconds = static_cast<double>(last - first) / 1e9;
  std::printf("check: %u/%u predictions (%u out of order, %u corrupted), %u grasps, %u acks, %u pongs, %zu commands unanswered\n",
              next_frame, a.frames, out_of_order, corrupted, grasps, acks, pongs, awaiting.size());
  std::printf("check: %.1f predictions/s; link: %llu frames, %llu rejected, %llu gaps (%llu missing), %llu reconnects\n",
              seconds > 0 ? (next_frame - 1) / seconds : 0.0, static_cast<unsigned long long>(s.frames.frames),
              static_cast<unsigned long long>(s.frames.rejected()), static_cast<unsigned long long>(s.sequence_gaps),
              static_cast<unsigned long long>(s.frames_missing), static_cast<unsigned long long>(s.connects > 0 ? s.connects - 1 : 0));
  std::printf("check: capture->receive p50 %.3f ms p99 %.3f ms; send->receive p99 %.3f ms; clock %+.3f ms +- %.3f ms\n",
              s.capture_latency.percentile(50) / 1e6, s.capture_latency.percentile(99) / 1e6,
              s.link_latency.percentile(99) / 1e6, s.clock.offset_ns / 1e6, s.clock.uncertainty_ns / 1e6);
  const bool ok = next_frame == a.frames && out_of_order == 0 && corrupted == 0 && awaiting.empty() && refused_ok;
  std::printf("check: %s\n", ok ? "PASS" : "FAIL");
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  if (!parse(argc, argv, a) || (a.mode == "board" && a.link.empty()) || (a.mode == "check" && a.source.empty()) ||
      (a.mode == "record" && a.file.empty())) {
    std::fprintf(stderr,
                 "usage: tlvlink_stream_check board --link LINK [--frames N] [--rate HZ] [--embedding] [--hold S] [--boot-id N]\n"
                 "       tlvlink_stream_check check --source SOURCE [--frames N] [--timeout S]\n"
                 "       tlvlink_stream_check record FILE [--cut]\n");
    return 2;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  if (a.mode == "board") return board(a);
  if (a.mode == "check") return check(a);
  Status s = listen::write_fixture_recording(a.file, a.cut);
  if (!s.ok()) return std::fprintf(stderr, "record: %s\n", s.error().message()), 1;
  return 0;
}
