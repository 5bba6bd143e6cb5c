// tlvlink_hil_feeder: simulated GelSight frames into a real V4L2 capture node, through vivid's
// output->capture loop (tests/capture/vivid/loop_feeder.h), for the hardware-in-the-loop run
// (tests/hil). The frames come from a camera recording (*.tlvraw, `tlvlink sim scenario`); its
// distinct frames (repeat records skipped) are fed one every --interval-ms, in order.
//   tlvlink_hil_feeder --recording FILE [--first K] [--count N] [--interval-ms MS] [--hold-s S]
//                      [--ready FILE]
// Feeds distinct frames K .. K+N-1, then keeps the last one on the output for S seconds (vivid
// repeats it) or until SIGTERM. --ready FILE is created once the loop runs (the script then
// makes the camera visible to the daemon). Exit 0 when every frame was fed; 3 when the output
// stopped taking frames (vivid unloaded under it); 1 on a set-up error, 2 on bad arguments.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "tlvlink/capture/recording.h"
#include "vivid/loop_feeder.h"
#include "vivid/vivid_support.h"

namespace {

using namespace tlvlink;

volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_signal(int) { g_stop = 1; }

struct Args {
  std::string recording, ready;
  uint32_t first = 0, count = 0;  // count 0: every distinct frame from first
  int32_t interval_ms = 250;
  double hold_s = 5;
};

bool parse(int argc, char** argv, Args& a) {
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (i + 1 >= argc) return false;
    const char* v = argv[++i];
    if (k == "--recording")
      a.recording = v;
    else if (k == "--ready")
      a.ready = v;
    else if (k == "--first")
      a.first = static_cast<uint32_t>(std::strtoul(v, nullptr, 10));
    else if (k == "--count")
      a.count = static_cast<uint32_t>(std::strtoul(v, nullptr, 10));
    else if (k == "--interval-ms")
      a.interval_ms = static_cast<int32_t>(std::strtol(v, nullptr, 10));
    else if (k == "--hold-s")
      a.hold_s = std::strtod(v, nullptr);
    else
      return false;
  }
  return !a.recording.empty() && a.interval_ms > 0;
}

double uptime_s() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  if (!parse(argc, argv, a)) {
    std::fprintf(stderr,
                 "usage: tlvlink_hil_feeder --recording FILE [--first K] [--count N] "
                 "[--interval-ms MS] [--hold-s S] [--ready FILE]\n");
    return 2;
  }
  std::signal(SIGTERM, on_signal);
  std::signal(SIGINT, on_signal);
  auto reader = capture::RecordingReader::open(a.recording);
  if (!reader.ok()) {
    std::fprintf(stderr, "feeder: %s\n", reader.error().message());
    return 1;
  }
  // The distinct frames, in recorded order.
  std::vector<capture::RecordInfo> frames;
  uint64_t at = reader->first_record();
  for (capture::RecordInfo info;;) {
    auto more = reader->record_at(at, info);
    if (!more.ok()) {
      std::fprintf(stderr, "feeder: %s\n", more.error().message());
      return 1;
    }
    if (!*more) break;
    if ((info.flags & capture::kRecordRepeat) == 0) frames.push_back(info);
    at = info.next;
  }
  const image::FrameFormat& rf = reader->summary().format.format;
  if (a.first >= frames.size()) {
    std::fprintf(stderr, "feeder: --first %u: %s has %zu distinct frames\n", a.first,
                 a.recording.c_str(), frames.size());
    return 2;
  }
  const uint32_t count =
      a.count == 0 ? static_cast<uint32_t>(frames.size()) - a.first
                   : std::min<uint32_t>(a.count, static_cast<uint32_t>(frames.size()) - a.first);
  auto nodes = capture::vivid::find_nodes();
  if (!nodes || nodes->output.empty()) {
    std::fprintf(stderr, "feeder: vivid with an output node is not loaded\n");
    return 1;
  }
  // Frame i fed = distinct frame first + min(i, count - 1): past the last, it stays on the output.
  const capture::RecordingReader& r = *reader;
  bool read_failed = false;
  auto fill = [&](uint32_t i, std::span<uint8_t> out) {
    const capture::RecordInfo& info = frames[a.first + std::min(i, count - 1)];
    if (out.size() != info.bytes || !r.read_frame(info, out, true).ok()) read_failed = true;
  };
  auto feeder = capture::vivid::LoopFeeder::start(*nodes, rf.format, fill);
  if (!feeder.ok()) {
    std::fprintf(stderr, "feeder: %s\n", feeder.error().message());
    return 1;
  }
  const image::FrameFormat& of = (*feeder)->format();
  if (of.width != rf.width || of.height != rf.height ||
      image::frame_bytes(of) != image::frame_bytes(rf)) {
    std::fprintf(
        stderr, "feeder: vivid's output is %dx%d (%zu bytes a frame), the recording %dx%d (%zu)\n",
        of.width, of.height, image::frame_bytes(of), rf.width, rf.height, image::frame_bytes(rf));
    return 1;
  }
  if (!a.ready.empty()) {
    if (std::FILE* f = std::fopen(a.ready.c_str(), "w")) std::fclose(f);
  }
  std::printf("feeder: frames %u..%u of %s (%zu distinct), every %d ms, from uptime %.3f\n",
              a.first, a.first + count - 1, a.recording.c_str(), frames.size(), a.interval_ms,
              uptime_s());
  std::fflush(stdout);
  (*feeder)->feed_every(a.interval_ms);
  // Frame 0 was queued at start; frames 1 .. count-1 follow, one per interval.
  uint32_t last = (*feeder)->frames_queued();
  double last_progress = uptime_s();
  while (!g_stop && (*feeder)->frames_queued() < count) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const uint32_t q = (*feeder)->frames_queued();
    if (q != last) last = q, last_progress = uptime_s();
    if (uptime_s() - last_progress > 4.0 * a.interval_ms / 1000.0 + 1.0) {
      std::printf(
          "feeder: the output stopped taking frames after %u (vivid gone?) at uptime %.3f\n", q,
          uptime_s());
      return 3;
    }
  }
  (*feeder)->feed_every(0);  // the last frame stays on the output
  if (g_stop) {              // "fed" means every frame: the scripts wait for it
    std::printf("feeder: stopped after %u of %u frames at uptime %.3f\n",
                (*feeder)->frames_queued(), count, uptime_s());
    return 0;
  }
  std::printf("feeder: fed %u frames (last at uptime %.3f)%s\n", (*feeder)->frames_queued(),
              uptime_s(), read_failed ? "; READ ERRORS" : "");
  std::fflush(stdout);
  const double until = uptime_s() + a.hold_s;
  while (!g_stop && uptime_s() < until) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  return read_failed ? 1 : 0;
}
