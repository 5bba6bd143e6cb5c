// tlvlink_stream_bench: figures of the stream (a program that prints them; not a timed test).
//  1. Wire bytes and encode / decode cost per message (encode = payload + frame; decode =
//     deframe + verify + read every field), median of repeated batches.
//  2. Added latency over a pty: a board process (the real Sender on a pty) posts two sensors at
//     60 fps each plus Stats once a second; the host process (the C++ client) timestamps each
//     prediction when decoded. Added latency = decoded on the host - infer_end_ns stamped on the
//     board just before post() (one machine, one CLOCK_MONOTONIC): queue + write + pty + read +
//     deframe + decode. p50/p99/p99.9/max.
//  3. Throughput: the board posts as fast as it can; messages/s decoded on the host.
//  With --realtime P the board's link thread (SenderConfig::realtime_priority) and the host's
//  reading thread run SCHED_FIFO at priority P, as a deployment on a busy board would set them.
//   tlvlink_stream_bench [--seconds S] [--burst N] [--realtime P]

#include <pthread.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "stream_fixture.h"
#include "tlvlink/listen/client.h"
#include "tlvlink/protocol/deframer.h"
#include "tlvlink/protocol/encode.h"
#include "tlvlink/protocol/views.h"
#include "tlvlink/transport/pty.h"
#include "tlvlink/transport/sender.h"
#include "tlvlink/transport/time.h"

namespace {

using namespace tlvlink;
using transport::monotonic_ns;

int g_realtime = 0;
alignas(8) std::byte g_scratch[protocol::kEncodeBufferSize];
std::byte g_wire[protocol::kMaxWireFrameSize];

// A FramePrediction as the shipped model produces it: 4 heads (material 12 labels, hardness 2,
// roughness 2, grasp 2), 5 stage latencies, optionally a 128-float embedding.
struct Realistic {
  std::array<float, 12> material{};
  std::array<float, 2> a{}, b{}, c{};
  std::array<protocol::HeadOutput, 4> heads{};
  std::array<uint32_t, 5> stages = {120'000, 2'500'000, 800'000, 1'100'000, 30'000};
  std::array<float, 128> embedding{};
  protocol::FramePrediction make(bool with_embedding) {
    for (size_t i = 0; i < material.size(); ++i) material[i] = 0.01f * static_cast<float>(i);
    a = {0.3f, 0.7f}, b = {0.6f, 0.4f}, c = {0.1f, 0.9f};
    for (size_t i = 0; i < embedding.size(); ++i) embedding[i] = 0.001f * static_cast<float>(i);
    heads = {protocol::HeadOutput{0, material}, protocol::HeadOutput{1, a},
             protocol::HeadOutput{2, b}, protocol::HeadOutput{3, c}};
    protocol::FramePrediction f;
    f.sensor = 1;
    f.frame_sequence = 123456;
    f.timing = {1'000'000'000, 1'004'000'000, 1'005'500'000};
    f.stage_ns = stages;
    f.contact = true;
    f.heads = heads;
    if (with_embedding) f.embedding = embedding;
    return f;
  }
};

template <typename M, typename Walk>
void cost(const char* name, const M& m, Walk walk) {
  constexpr int kBatch = 2000,
                kRounds = 15;  // fastest batch: the uncontended cost on a shared machine
  protocol::FrameHeader h;
  size_t wire = 0;
  std::vector<double> enc, dec;
  static protocol::Deframer deframer;
  for (int r = 0; r < kRounds; ++r) {
    int64_t t0 = monotonic_ns();
    for (int i = 0; i < kBatch; ++i) {
      h.sequence = static_cast<uint32_t>(i);
      wire = protocol::encode_message(m, h, g_scratch, g_wire).value();
    }
    enc.push_back(static_cast<double>(monotonic_ns() - t0) / kBatch);
    t0 = monotonic_ns();
    for (int i = 0; i < kBatch; ++i) {
      deframer.feed(std::span<const std::byte>(g_wire, wire),
                    [&](const protocol::ReceivedFrame& f) {
                      if (f.verdict == protocol::FrameVerdict::kOk) walk(f.payload);
                    });
    }
    dec.push_back(static_cast<double>(monotonic_ns() - t0) / kBatch);
  }
  std::sort(enc.begin(), enc.end());
  std::sort(dec.begin(), dec.end());
  std::printf("| %-34s | %5zu | %6.2f / %6.2f | %6.2f / %6.2f |\n", name, wire, enc[0] / 1000,
              enc[kRounds / 2] / 1000, dec[0] / 1000, dec[kRounds / 2] / 1000);
}

volatile double g_sink;

void costs() {
  std::printf(
      "## Wire bytes and cost per message (15 batches of 2000: fastest batch / median; one "
      "core)\n\n");
  std::printf(
      "| message | wire bytes | encode us (min / median) | decode us (min / median) "
      "|\n|---|---|---|---|\n");
  Realistic r;
  auto walk_frame = [](std::span<const std::byte> p) {
    auto v = protocol::decode_frame_prediction(p).value();
    double s = 0;
    for (size_t i = 0; i < v.head_count(); ++i) {
      for (float x : v.head(i).probabilities) s += static_cast<double>(x);
    }
    for (float x : v.embedding()) s += static_cast<double>(x);
    g_sink = s + static_cast<double>(v.timing().capture_ns);
  };
  cost("FramePrediction, 4 heads (18 probs)", r.make(false), walk_frame);
  cost("FramePrediction + 128-d embedding", r.make(true), walk_frame);
  testing::PredictionStorage st;
  cost("FramePrediction, fixture (2 heads)", testing::fixture_prediction(7, st), walk_frame);
  const std::array<protocol::GraspFrame, 4> frames{};
  protocol::GraspPrediction g;
  g.status = protocol::GraspStatus::kComputed;
  g.probability = 0.8f;
  g.frames = frames;
  cost("GraspPrediction (4 frames)", g, [](std::span<const std::byte> p) {
    g_sink = protocol::decode_grasp_prediction(p).value().probability();
  });
  const std::array<protocol::SensorStats, 2> ss{};
  const std::array<protocol::DropCount, 6> drops{};
  protocol::Stats s;
  s.sensors = ss;
  s.drops = drops;
  cost("Stats (2 sensors, 6 drop causes)", s, [](std::span<const std::byte> p) {
    auto v = protocol::decode_stats(p).value();
    g_sink = static_cast<double>(v.link().frames_sent + v.drop_count());
  });
  cost("Hello (fixture)", testing::fixture_hello(), [](std::span<const std::byte> p) {
    g_sink = static_cast<double>(protocol::decode_hello(p).value().head_count());
  });
  std::printf("\n");
}

// The board side of sections 2 and 3, in a child process: `paced` posts two sensors at 60 fps
// plus Stats each second for `seconds`; otherwise posts `burst` predictions as fast as it can.
int board(const std::string& link, bool paced, double seconds, uint32_t burst, int report_fd) {
  transport::SenderConfig config;
  config.queue_bytes = 1 << 20;
  config.flush_ms = 5000;
  config.realtime_priority = g_realtime;
  auto sender = transport::Sender::create(
                    std::make_unique<transport::PtyTransport>(transport::PtyConfig{link}), config)
                    .value();
  (void)sender->set_hello(testing::fixture_hello());
  (void)sender->start();
  // Wait for the host to connect (the Hello is sent once it is there).
  for (int i = 0; i < 500 && !sender->counters().link_up; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // its clock-sync burst settles
  Realistic r;
  protocol::FramePrediction f = r.make(false);
  uint32_t n = 0;
  if (paced) {
    const int64_t period = 1'000'000'000 / 60;
    const int64_t start = monotonic_ns();
    int64_t next = start, next_stats = start + 1'000'000'000;
    while (monotonic_ns() - start < static_cast<int64_t>(seconds * 1e9)) {
      for (uint8_t sensor = 0; sensor < 2; ++sensor) {
        f.sensor = sensor, f.frame_sequence = n++;
        f.timing.capture_ns = monotonic_ns() - 3'000'000;
        f.timing.infer_end_ns = monotonic_ns();
        (void)sender->post(f);
      }
      if (monotonic_ns() >= next_stats) {
        (void)sender->post(protocol::Stats{});
        next_stats += 1'000'000'000;
      }
      next += period;
      std::this_thread::sleep_until(
          std::chrono::steady_clock::time_point(std::chrono::nanoseconds(next)));
    }
  } else {
    for (; n < burst; ++n) {
      f.frame_sequence = n;
      f.timing.infer_end_ns = monotonic_ns();
      (void)sender->post(f);
    }
  }
  sender->stop();
  const transport::SenderCounters c = sender->counters();
  char line[256];
  const int len = std::snprintf(
      line, sizeof(line), "%u %llu %llu %llu\n", n, static_cast<unsigned long long>(c.frames_sent),
      static_cast<unsigned long long>(c.dropped_queue_full + c.dropped_link_down),
      static_cast<unsigned long long>(c.bytes_sent));
  (void)!::write(report_fd, line, static_cast<size_t>(len));
  return 0;
}

struct HostResult {
  std::vector<int64_t> latency;
  std::vector<int64_t> board_part;  // post -> frame written (the header's send time)
  std::vector<int64_t> link_part;   // frame written -> decoded on the host
  uint64_t predictions = 0;
  int64_t first = 0, last = 0;
  listen::LinkStats stats;
};

HostResult host(const std::string& link, uint32_t expect, double timeout_s) {
  HostResult h;
  if (g_realtime > 0) {
    sched_param param{};
    param.sched_priority = g_realtime;
    if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) != 0)
      std::printf("(host: SCHED_FIFO refused)\n");
  }
  auto client = listen::Client::open("serial:" + link).value();
  const int64_t end = monotonic_ns() + static_cast<int64_t>(timeout_s * 1e9);
  while (monotonic_ns() < end && h.predictions < expect) {
    Result<std::optional<listen::Message>> m = client->next(50);
    if (!m.ok() || !m.value()) continue;
    auto f = m.value()->frame_prediction();
    if (!f.ok()) continue;
    const int64_t decoded = monotonic_ns();
    h.latency.push_back(decoded - f.value().timing().infer_end_ns);
    h.board_part.push_back(m.value()->send_ns() - f.value().timing().infer_end_ns);
    h.link_part.push_back(decoded - m.value()->send_ns());
    if (h.first == 0) h.first = decoded;
    h.last = decoded;
    ++h.predictions;
  }
  h.stats = client->stats();
  return h;
}

double pct(std::vector<int64_t> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t k = std::min(
      v.size() - 1, static_cast<size_t>(std::ceil(p / 100 * static_cast<double>(v.size()))) - 1);
  return static_cast<double>(v[k]) / 1e6;
}

void run(bool paced, double seconds, uint32_t burst) {
  char dir_template[] = "/tmp/tlvlink_bench_XXXXXX";
  const std::string link = std::string(::mkdtemp(dir_template)) + "/tty";
  int fds[2];
  if (::pipe(fds) != 0) return;
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    std::_Exit(board(link, paced, seconds, burst, fds[1]));
  }
  ::close(fds[1]);
  for (int i = 0; i < 300 && ::access(link.c_str(), F_OK) != 0; ++i) ::usleep(10'000);
  const uint32_t expect = paced ? static_cast<uint32_t>(seconds * 120) : burst;
  const HostResult h = host(link, expect, seconds + 30);
  char report[256] = {};
  (void)!::read(fds[0], report, sizeof(report) - 1);
  ::close(fds[0]);
  ::waitpid(pid, nullptr, 0);
  unsigned posted = 0;
  unsigned long long sent = 0, dropped = 0, bytes = 0;
  std::sscanf(report, "%u %llu %llu %llu", &posted, &sent, &dropped, &bytes);
  const double span = static_cast<double>(h.last - h.first) / 1e9;
  if (paced) {
    std::printf("## Added latency over a pty: 2 sensors x 60 fps + Stats 1/s for %.0f s\n\n",
                seconds);
    std::printf(
        "| predictions posted / decoded | board drops | p50 ms | p90 ms | p99 ms | p99.9 ms | max "
        "ms | messages/s |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    std::printf("| %u / %llu | %llu | %.3f | %.3f | %.3f | %.3f | %.3f | %.1f |\n\n", posted,
                static_cast<unsigned long long>(h.predictions), dropped, pct(h.latency, 50),
                pct(h.latency, 90), pct(h.latency, 99), pct(h.latency, 99.9), pct(h.latency, 100),
                span > 0 ? static_cast<double>(h.predictions - 1) / span : 0.0);
    std::printf("| part | p50 ms | p99 ms | max ms |\n|---|---|---|---|\n");
    std::printf(
        "| board: post -> written (queue, link thread wake-up, encode) | %.3f | %.3f | %.3f |\n",
        pct(h.board_part, 50), pct(h.board_part, 99), pct(h.board_part, 100));
    std::printf(
        "| link + host: written -> decoded (pty, read, deframe, decode) | %.3f | %.3f | %.3f |\n\n",
        pct(h.link_part, 50), pct(h.link_part, 99), pct(h.link_part, 100));
    std::printf(
        "send -> receive (the client's own statistics, header send time to read): p50 %.3f ms, p99 "
        "%.3f ms; "
        "clock offset estimate %+.3f ms +- %.3f ms (true offset 0)\n\n",
        static_cast<double>(h.stats.link_latency.percentile(50)) / 1e6,
        static_cast<double>(h.stats.link_latency.percentile(99)) / 1e6,
        static_cast<double>(h.stats.clock.offset_ns) / 1e6,
        static_cast<double>(h.stats.clock.uncertainty_ns) / 1e6);
  } else {
    std::printf("## Throughput over a pty: %u predictions posted as fast as possible\n\n", burst);
    std::printf(
        "| posted | decoded | board drops | decoded/s | wire MB/s | mean wire bytes "
        "|\n|---|---|---|---|---|---|\n");
    std::printf("| %u | %llu | %llu | %.0f | %.2f | %.1f |\n\n", posted,
                static_cast<unsigned long long>(h.predictions), dropped,
                span > 0 ? static_cast<double>(h.predictions - 1) / span : 0.0,
                span > 0 ? static_cast<double>(h.stats.frames.bytes) / span / 1e6 : 0.0,
                sent ? static_cast<double>(bytes) / static_cast<double>(sent) : 0.0);
  }
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 20;
  uint32_t burst = 50000;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--seconds")
      seconds = std::strtod(argv[i + 1], nullptr);
    else if (k == "--burst")
      burst = static_cast<uint32_t>(std::strtoul(argv[i + 1], nullptr, 10));
    else if (k == "--realtime")
      g_realtime = std::atoi(argv[i + 1]);
  }
  double load[3] = {};
  if (::getloadavg(load, 3) == 3) {
    std::printf("tlvlink_stream_bench: %u cores, load average %.2f %.2f %.2f; link threads %s\n\n",
                std::thread::hardware_concurrency(), load[0], load[1], load[2],
                g_realtime > 0 ? "SCHED_FIFO (--realtime)" : "SCHED_OTHER (default)");
  }
  costs();
  run(true, seconds, 0);
  run(false, 0, burst);
  return 0;
}
