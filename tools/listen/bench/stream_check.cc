// tlvlink_stream_check: the stream end to end over any link, in two processes (or two machines,
// or the emulated board and its USB host side):
//   tlvlink_stream_check board --link LINK [--frames N] [--rate HZ] [--embedding] [--hold S]
//   [--boot-id N]
//                              [--byte-errors P] [--byte-drops Q] [--seed S] [--wait-host S]
//                              [--images K]
//       a board: the Sender on LINK (make_transport: serial:PATH, pty:LINK, usb[:FFS_DIR,...])
//       posting N fixture predictions at HZ (sensor n % 2: 120 Hz = two sensors at 60 fps; 0 = as
//       fast as the poster can; every 10th frame also a grasp), Stats every second, answering
//       commands (set bad=... is refused); then holds the link S seconds and flushes. With
//       --wait-host S it posts nothing until a host has synchronised its clock (a listener that
//       opens the link late misses nothing; at most S seconds, then it posts anyway). With
//       --byte-errors/--byte-drops the bytes are damaged between the Sender and the link
//       (corrupting_transport.h), so the damage crosses the real wire. --images K: after every
//       K-th prediction a FrameImage of its frame (a 64x48 JPEG, a 32x24 contact mask marking
//       a block that moves with the frame number; kind view, contact on odd images).
//   tlvlink_stream_check check --source SOURCE [--frames N] [--timeout S] [--clean | --lossy]
//                              [--start-any] [--no-commands] [--expect-reconnects K]
//                              [--expect-board-reconnects K] [--idle S] [--label NAME]
//       a host: the Client on SOURCE (serial:PATH, usb[:VID:PID][,serial=S]); sends ping, info,
//       start, closed 1, set bad=1; by default expects every prediction 0..N-1 intact and in order
//       and each command answered (the last refused); --clean also no rejected frame, no
//       sequence gap and no reconnect on either side. --lossy (a damaged link, a reader restarted,
//       an unplug): predictions may be missing and resent ones repeated, but none may be corrupted
//       or go backwards, and the last one (N-1) must arrive unless --no-commands (the corruption
//       runs) ends the check when no prediction came for --idle S. --start-any: a reader started
//       mid-stream counts from the first prediction it gets. --expect-reconnects K: the client
//       reconnected at least K times;
//       --expect-board-reconnects K: the board's Stats report at least K reconnects. Prints what
//       it got, figures as "note:" lines (the emulated board's report keeps them) and one
//       "check-summary" line of key=value; exit 0 when all is well.
//   tlvlink_stream_check record FILE [--cut]
//       writes the deterministic fixture recording (fixture_recording.h).
// In this repository it runs over a pty (tests/listen); in the emulated board over CDC-ACM and
// the FunctionFS gadget through dummy_hcd (tools/rig).

#include <algorithm>
#include <array>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "fixture_recording.h"
#if defined(TLVLINK_STREAM_CHECK_IMAGES)
#include "tlvlink/image/jpeg.h"
#endif
#include "corrupting_transport.h"
#include "stream_fixture.h"
#include "tlvlink/listen/client.h"
#include "tlvlink/listen/command_text.h"
#include "tlvlink/protocol/names.h"
#include "tlvlink/transport/sender.h"
#include "tlvlink/transport/time.h"
#include "tlvlink/transport/transport_spec.h"

namespace {

using namespace tlvlink;
using transport::monotonic_ns;

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop = true; }

struct Args {
  std::string mode, link, source, file, label = "stream";
  uint32_t frames = 100, expect_reconnects = 0, expect_board_reconnects = 0;
  double rate = 120, hold_s = 1, timeout_s = 30, idle_s = 3, wait_host_s = 0;
  double byte_errors = 0, byte_drops = 0;
  uint64_t boot_id = 0x5EED, seed = 1;
  uint32_t images = 0;
  bool embedding = false, cut = false, clean = false, lossy = false, start_any = false,
       commands = true;
};

bool parse(int argc, char** argv, Args& a) {
  if (argc < 2) return false;
  a.mode = argv[1];
  for (int i = 2; i < argc; ++i) {
    const std::string k = argv[i];
    auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : ""; };
    if (k == "--link")
      a.link = value();
    else if (k == "--source")
      a.source = value();
    else if (k == "--frames")
      a.frames = static_cast<uint32_t>(std::strtoul(value(), nullptr, 10));
    else if (k == "--rate")
      a.rate = std::strtod(value(), nullptr);
    else if (k == "--hold")
      a.hold_s = std::strtod(value(), nullptr);
    else if (k == "--wait-host")
      a.wait_host_s = std::strtod(value(), nullptr);
    else if (k == "--timeout")
      a.timeout_s = std::strtod(value(), nullptr);
    else if (k == "--embedding")
      a.embedding = true;
    else if (k == "--boot-id")
      a.boot_id = std::strtoull(value(), nullptr, 0);
    else if (k == "--cut")
      a.cut = true;
    else if (k == "--byte-errors")
      a.byte_errors = std::strtod(value(), nullptr);
    else if (k == "--byte-drops")
      a.byte_drops = std::strtod(value(), nullptr);
    else if (k == "--seed")
      a.seed = std::strtoull(value(), nullptr, 0);
    else if (k == "--clean")
      a.clean = true;
    else if (k == "--lossy")
      a.lossy = true;
    else if (k == "--start-any")
      a.start_any = true;
    else if (k == "--no-commands")
      a.commands = false;
    else if (k == "--expect-reconnects")
      a.expect_reconnects = static_cast<uint32_t>(std::strtoul(value(), nullptr, 10));
    else if (k == "--expect-board-reconnects")
      a.expect_board_reconnects = static_cast<uint32_t>(std::strtoul(value(), nullptr, 10));
    else if (k == "--idle")
      a.idle_s = std::strtod(value(), nullptr);
    else if (k == "--label")
      a.label = value();
    else if (k == "--images")
      a.images = static_cast<uint32_t>(std::strtoul(value(), nullptr, 10));
    else if (a.mode == "record" && a.file.empty())
      a.file = k;
    else
      return false;
  }
  return true;
}

// The fixture's FrameImage of prediction n (its sensor, sequence and capture time).
struct FixtureImage {
  std::vector<uint8_t> jpeg;
  std::array<uint8_t, 32 * 24 / 8> mask{};
};
bool make_fixture_jpeg(FixtureImage& out) {
#if !defined(TLVLINK_STREAM_CHECK_IMAGES)
  (void)out;
  return false;  // built without tlvlink_image
#else
  std::vector<uint8_t> rgb(64 * 48 * 3);
  for (size_t i = 0; i < rgb.size(); ++i)
    rgb[i] = static_cast<uint8_t>(90 + (i / 3) % 64 + (i % 3) * 30);
  image::JpegEncoder encoder;
  auto j = encoder.encode({rgb.data(), 64, 48, 3, 0}, 70, image::JpegEncoder::Subsampling::k420);
  if (!j.ok()) return false;
  out.jpeg.assign(j.value().begin(), j.value().end());
  return true;
#endif
}
protocol::FrameImage fixture_image(const protocol::FramePrediction& p, uint32_t k,
                                   FixtureImage& storage) {
  storage.mask.fill(0);
  const uint32_t cell = (k * 37) % (32 * 24);
  storage.mask[cell / 8] = static_cast<uint8_t>(1u << (cell % 8));
  protocol::FrameImage m;
  m.sensor = p.sensor;
  m.frame_sequence = p.frame_sequence;
  m.capture_ns = p.timing.capture_ns;
  m.kind = protocol::ImageKind::kView;
  m.width = 64;
  m.height = 48;
  m.contact = k % 2 == 1;
  m.mask_width = 32;
  m.mask_height = 24;
  m.mask = storage.mask;
  m.data = storage.jpeg;
  return m;
}

int board(const Args& a) {
  FixtureImage image;
  if (a.images > 0 && !make_fixture_jpeg(image))
    return std::fprintf(stderr, "board: no fixture JPEG (built without tlvlink_image?)\n"), 2;
  Result<std::unique_ptr<transport::Transport>> link = transport::make_transport(a.link);
  if (!link.ok()) return std::fprintf(stderr, "board: %s\n", link.error().message()), 2;
  std::unique_ptr<transport::Transport> wire = std::move(link.value());
  testing::CorruptingTransport* damage = nullptr;
  if (a.byte_errors > 0 || a.byte_drops > 0) {
    auto t = std::make_unique<testing::CorruptingTransport>(
        std::move(wire), testing::ByteFaultRates{a.byte_errors, a.byte_drops, a.seed});
    damage = t.get();
    wire = std::move(t);
  }
  Result<std::unique_ptr<transport::Sender>> s = transport::Sender::create(std::move(wire), {});
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
  // A host that talks has sent TimeSyncs with its estimate (the listener does so at connect).
  for (int64_t end = monotonic_ns() + static_cast<int64_t>(a.wait_host_s * 1e9);
       monotonic_ns() < end && !sender.host_clock().valid && !g_stop;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const int64_t period = a.rate > 0 ? static_cast<int64_t>(1e9 / a.rate) : 0;
  int64_t next = monotonic_ns(), next_stats = next + 1'000'000'000;
  testing::PredictionStorage st;
  for (uint32_t n = 0; n < a.frames && !g_stop; ++n) {
    const protocol::FramePrediction prediction =
        testing::fixture_prediction(n, st, a.embedding, monotonic_ns());
    (void)sender.post(prediction);
    if (a.images > 0 && n % a.images == a.images - 1)
      (void)sender.post(fixture_image(prediction, n / a.images, image));
    if (n % 10 == 9) {
      protocol::GraspPrediction g;
      g.grasp_id = n / 10;
      g.status =
          (n / 10) % 2 ? protocol::GraspStatus::kNotComputed : protocol::GraspStatus::kComputed;
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
  for (int64_t end = monotonic_ns() + static_cast<int64_t>(a.hold_s * 1e9);
       monotonic_ns() < end && !g_stop;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  (void)sender.post(protocol::Stats{});
  sender.stop();
  const transport::SenderCounters c = sender.counters();
  std::printf(
      "board: posted %llu, sent %llu frames (%llu bytes, %llu delayed), dropped %llu queue_full "
      "%llu link_down, "
      "%u reconnects, %llu commands (%llu refused)\n",
      static_cast<unsigned long long>(c.posted), static_cast<unsigned long long>(c.frames_sent),
      static_cast<unsigned long long>(c.bytes_sent),
      static_cast<unsigned long long>(c.delayed_sent),
      static_cast<unsigned long long>(c.dropped_queue_full),
      static_cast<unsigned long long>(c.dropped_link_down), c.reconnects,
      static_cast<unsigned long long>(c.commands),
      static_cast<unsigned long long>(c.commands_refused));
  // Every message the board lost, by cause (a reader restarted while nobody read: tests/python).
  std::printf("board-drops queue_full=%llu link_down=%llu stale=%llu\n",
              static_cast<unsigned long long>(c.dropped_queue_full),
              static_cast<unsigned long long>(c.dropped_link_down),
              static_cast<unsigned long long>(c.dropped_stale));
  std::printf(
      "note: board: %.1f wire bytes per frame (%llu frames, %llu bytes)\n",
      c.frames_sent ? static_cast<double>(c.bytes_sent) / static_cast<double>(c.frames_sent) : 0.0,
      static_cast<unsigned long long>(c.frames_sent),
      static_cast<unsigned long long>(c.bytes_sent));
  if (damage) {
    const testing::ByteFaultCounts d = damage->counts();
    std::printf("board-damage bytes=%llu corrupted=%llu dropped=%llu queue_drops=%llu\n",
                static_cast<unsigned long long>(d.bytes),
                static_cast<unsigned long long>(d.corrupted),
                static_cast<unsigned long long>(d.dropped),
                static_cast<unsigned long long>(c.dropped_queue_full + c.dropped_link_down +
                                                c.dropped_stale));
  }
  return 0;
}

double percentile_ms(std::vector<int64_t>& v, double p) {
  if (v.empty()) return 0;
  const size_t i =
      std::min(v.size() - 1, static_cast<size_t>(p / 100.0 * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(i), v.end());
  return static_cast<double>(v[i]) / 1e6;
}

int check(const Args& a) {
  Result<std::unique_ptr<listen::Client>> c = listen::Client::open(a.source);
  if (!c.ok()) return std::fprintf(stderr, "check: %s\n", c.error().message()), 2;
  listen::Client& client = *c.value();
  const char* commands[] = {"ping", "info", "start", "closed 1", "set bad=1"};
  std::set<uint32_t> awaiting;
  uint32_t refused_seq = 0;
  bool sent = !a.commands, refused_ok = !a.commands;
  // Every prediction seen (by frame number), in arrival order checks.
  std::vector<bool> seen(a.frames, false);
  std::vector<int64_t>
      added;  // post on the board -> decoded here (one CLOCK_MONOTONIC in one machine)
  added.reserve(a.frames);
  uint32_t next_frame = 0, out_of_order = 0, corrupted = 0, grasps = 0, acks = 0, pongs = 0;
  uint32_t unique = 0, duplicates = 0, backward = 0, beyond = 0, board_reconnects = 0;
  int64_t first_frame = -1, last_frame = -1, first_decoded = 0;
  const int64_t start = monotonic_ns(), deadline = start + static_cast<int64_t>(a.timeout_s * 1e9);
  int64_t first = 0, last = 0;
  // Rejects before the first intact frame are the tail of a frame sent before this reader opened
  // the link (a CDC-ACM gadget buffers what the board wrote while nobody listened): joining a
  // stream mid-frame, not damage. A clean link allows those, and no other.
  uint64_t rejected_at_join = 0;
  bool joined = false;
  auto done = [&] {
    const bool answered = awaiting.empty() && sent;
    if (!a.lossy) return next_frame >= a.frames && answered;
    if (last_frame == static_cast<int64_t>(a.frames) - 1 && answered) return true;
    // Without commands (a damaged link) the last prediction may itself be lost: stop when the
    // stream went quiet.
    return !a.commands && first != 0 &&
           monotonic_ns() - last > static_cast<int64_t>(a.idle_s * 1e9);
  };
  while (!g_stop && monotonic_ns() < deadline && !done()) {
    Result<std::optional<listen::Message>> m = client.next(100);
    for (const listen::LinkEvent& e : client.take_events()) {
      std::printf("check: %s: %s\n", listen::link_event_name(e.kind), e.text.c_str());
    }
    if (!m.ok()) return std::fprintf(stderr, "check: %s\n", m.error().message()), 1;
    if (!m.value()) continue;
    if (!joined) rejected_at_join = client.stats().frames.rejected(), joined = true;
    const int64_t decoded_ns = monotonic_ns();
    const listen::Message& msg = *m.value();
    if (msg.type() == protocol::MessageType::kHello && !sent) {
      for (const char* text : commands) {
        Result<uint32_t> seq = client.send(listen::parse_command(text).value());
        if (!seq.ok())
          return std::fprintf(stderr, "check: sending '%s': %s\n", text, seq.error().message()), 1;
        awaiting.insert(seq.value());
        if (std::strncmp(text, "set bad", 7) == 0) refused_seq = seq.value();
      }
      sent = true;
    }
    if (auto f = msg.frame_prediction(); f.ok()) {
      const uint32_t n = f.value().frame_sequence();
      if (!testing::fixture_prediction_intact(f.value())) {
        ++corrupted;
        continue;
      }
      if (n != next_frame) ++out_of_order;
      next_frame = n + 1;
      if (n >= a.frames) {
        ++beyond;
      } else if (seen[n]) {
        ++duplicates;  // resent after a disconnect
        if (duplicates <= 5) {
          std::printf("check: prediction %u again (frame sequence %u%s)\n", n, msg.sequence(),
                      msg.delayed() ? ", delayed" : "");
        }
      } else {
        seen[n] = true;
        ++unique;
        if (static_cast<int64_t>(n) < last_frame && ++backward <= 5) {
          std::printf("check: prediction %u after %lld (frame sequence %u%s)\n", n,
                      static_cast<long long>(last_frame), msg.sequence(),
                      msg.delayed() ? ", delayed" : "");
        }
        if (first_frame < 0) first_frame = n;
        last_frame = std::max<int64_t>(last_frame, n);
        // Steady state only: not the backlog of a (re)connect (flagged delayed, or in the first
        // second after the first prediction arrived).
        if (first_decoded == 0) first_decoded = decoded_ns;
        if (!msg.delayed() && decoded_ns - first_decoded > 1'000'000'000 &&
            added.size() < added.capacity()) {
          added.push_back(decoded_ns - f.value().timing().capture_ns);
        }
      }
      if (first == 0) first = msg.receive_ns();
      last = msg.receive_ns();
    }
    if (auto st = msg.stats(); st.ok())
      board_reconnects = std::max(board_reconnects, st.value().link().reconnects);
    if (msg.grasp_prediction().ok()) ++grasps;
    if (auto p = msg.pong(); p.ok()) awaiting.erase(p.value().command_sequence), ++pongs;
    if (auto k = msg.ack(); k.ok()) awaiting.erase(k.value().command_sequence), ++acks;
    if (auto n = msg.nack(); n.ok()) {
      awaiting.erase(n.value().command_sequence);
      refused_ok = n.value().command_sequence == refused_seq;
    }
  }
  const listen::LinkStats s = client.stats();
  const uint64_t reconnects = s.connects > 0 ? s.connects - 1 : 0;
  const uint32_t counted_from =
      a.start_any && first_frame > 0 ? static_cast<uint32_t>(first_frame) : 0;
  const uint32_t expected = a.frames - counted_from;
  const uint32_t lost = expected - std::min(expected, unique);
  const double seconds = static_cast<double>(last - first) / 1e9;
  const double rate = seconds > 0 && unique > 1 ? (unique - 1) / seconds : 0.0;
  const protocol::DeframerCounters& r = s.frames;
  std::printf(
      "check: %u/%u predictions (%u out of order, %u corrupted, %u repeated, %u lost), %u grasps, "
      "%u acks, "
      "%u pongs, %zu commands unanswered\n",
      unique, expected, out_of_order, corrupted, duplicates, lost, grasps, acks, pongs,
      awaiting.size());
  std::printf(
      "check: %.1f predictions/s; link: %llu frames, %llu rejected, %llu gaps (%llu missing), %llu "
      "reconnects; "
      "board reports %u reconnects\n",
      rate, static_cast<unsigned long long>(r.frames),
      static_cast<unsigned long long>(r.rejected()),
      static_cast<unsigned long long>(s.sequence_gaps),
      static_cast<unsigned long long>(s.frames_missing),
      static_cast<unsigned long long>(reconnects), board_reconnects);
  const size_t n_added = added.size();
  const double p50 = percentile_ms(added, 50), p99 = percentile_ms(added, 99);
  std::printf(
      "note: %s: %u predictions at %.1f/s; added latency post->decoded p50 %.3f ms p99 %.3f ms "
      "(%zu samples after the first second, none delayed); "
      "clock %+.3f ms +- %.3f ms\n",
      a.label.c_str(), unique, rate, p50, p99, n_added, s.clock.offset_ns / 1e6,
      s.clock.uncertainty_ns / 1e6);
  std::printf(
      "check-summary label=%s expected=%u received=%u lost=%u repeated=%u corrupted_accepted=%u "
      "rejected=%llu crc=%llu cobs=%llu truncated=%llu length=%llu other=%llu gaps=%llu "
      "missing=%llu "
      "reconnects=%llu board_reconnects=%u rate=%.1f p50_ms=%.3f p99_ms=%.3f\n",
      a.label.c_str(), expected, unique, lost, duplicates, corrupted,
      static_cast<unsigned long long>(r.rejected()), static_cast<unsigned long long>(r.crc),
      static_cast<unsigned long long>(r.cobs), static_cast<unsigned long long>(r.truncated),
      static_cast<unsigned long long>(r.length),
      static_cast<unsigned long long>(r.magic + r.version + r.flags + r.oversized),
      static_cast<unsigned long long>(s.sequence_gaps),
      static_cast<unsigned long long>(s.frames_missing),
      static_cast<unsigned long long>(reconnects), board_reconnects, rate, p50, p99);
  // What must hold.
  std::vector<std::string> why;
  if (corrupted != 0) why.push_back("corrupted predictions accepted");
  if (beyond != 0) why.push_back("predictions beyond the last one");
  if (!a.lossy) {
    if (unique != a.frames || out_of_order != 0) why.push_back("not every prediction in order");
  } else {
    if (backward != 0) why.push_back("predictions went backwards");
    if (unique == 0) why.push_back("no prediction");
    if (a.commands && last_frame != static_cast<int64_t>(a.frames) - 1)
      why.push_back("the last prediction never came");
  }
  if (a.commands && (!awaiting.empty() || !refused_ok))
    why.push_back("commands unanswered or not refused");
  if (rejected_at_join != 0) {
    std::printf(
        "check: %llu rejected before the first intact frame (joined the stream mid-frame)\n",
        static_cast<unsigned long long>(rejected_at_join));
  }
  if (a.clean && (r.rejected() != rejected_at_join || s.sequence_gaps != 0 || reconnects != 0 ||
                  board_reconnects != 0)) {
    why.push_back("rejected frames, gaps or reconnects on a clean link");
  }
  if (reconnects < a.expect_reconnects) why.push_back("the client did not reconnect");
  if (board_reconnects < a.expect_board_reconnects)
    why.push_back("the board did not report its reconnect");
  std::string text;
  for (const std::string& w : why) text += (text.empty() ? "" : "; ") + w;
  std::printf("check: %s%s%s\n", why.empty() ? "PASS" : "FAIL", why.empty() ? "" : ": ",
              text.c_str());
  return why.empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  if (!parse(argc, argv, a) || (a.mode == "board" && a.link.empty()) ||
      (a.mode == "check" && a.source.empty()) || (a.mode == "record" && a.file.empty())) {
    std::fprintf(stderr,
                 "usage: tlvlink_stream_check board --link LINK [--frames N] [--rate HZ] "
                 "[--embedding] [--hold S] [--boot-id N] [--wait-host S]\n"
                 "                                  [--byte-errors P] [--byte-drops Q] [--seed S] "
                 "[--images K]\n"
                 "       tlvlink_stream_check check --source SOURCE [--frames N] [--timeout S] "
                 "[--clean | --lossy] [--start-any]\n"
                 "                                  [--no-commands] [--expect-reconnects K] "
                 "[--expect-board-reconnects K]\n"
                 "                                  [--idle S] [--label NAME]\n"
                 "       tlvlink_stream_check record FILE [--cut]\n");
    return 2;
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // lines reach a log even if the process is killed
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  if (a.mode == "board") return board(a);
  if (a.mode == "check") return check(a);
  Status s = listen::write_fixture_recording(a.file, a.cut);
  if (!s.ok()) return std::fprintf(stderr, "record: %s\n", s.error().message()), 1;
  return 0;
}
