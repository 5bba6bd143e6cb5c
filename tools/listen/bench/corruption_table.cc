// tlvlink_corruption_table: frames lost vs frames corrupted on a damaged serial line. A board
// (the real Sender) streams fixture predictions through a pty "cable" that replaces bytes with
// random different ones and drops bytes at stated rates (seeded); the C++ client on the other
// end checks every field of every prediction it accepts. A corrupted frame accepted would be a
// failure of the protocol; lost frames are the price of the damage. Prints a table.
//   tlvlink_corruption_table [--frames N] [--rate HZ] [--seed S]

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <thread>

#include "pty_cable.h"
#include "stream_fixture.h"
#include "tlvlink/listen/client.h"
#include "tlvlink/transport/sender.h"
#include "tlvlink/transport/serial.h"
#include "tlvlink/transport/time.h"

namespace {

using namespace tlvlink;
using transport::monotonic_ns;

struct Case {
  double error_rate, drop_rate;
};

struct Outcome {
  uint64_t sent = 0, intact = 0, corrupted = 0, duplicates = 0, bytes = 0, byte_errors = 0,
           byte_drops = 0;
  protocol::DeframerCounters rejected;
  uint64_t gaps = 0, missing = 0;
  double mean_wire_bytes = 0;
};

Outcome run_case(const Case& c, uint32_t frames, double rate, uint64_t seed) {
  Outcome o;
  char dir_template[] = "/tmp/tlvlink_corruption_XXXXXX";
  const std::string dir = ::mkdtemp(dir_template);
  testing::PtyCable cable(dir, testing::PtyCable::Faults{c.error_rate, c.drop_rate, seed});
  if (!cable.plug().ok()) return o;
  auto sender =
      transport::Sender::create(
          transport::make_serial_transport({cable.board_path(), 0, transport::FlowControl::kNone})
              .value(),
          {})
          .value();
  (void)sender->set_hello(testing::fixture_hello());
  (void)sender->start();
  auto client = listen::Client::open("serial:" + cable.host_path()).value();
  // Let the link come up (the Hello may itself be damaged: no need to wait for it).
  for (int64_t end = monotonic_ns() + 300'000'000; monotonic_ns() < end;) (void)client->next(20);
  std::set<uint32_t> seen;
  testing::PredictionStorage st;
  const int64_t period = static_cast<int64_t>(1e9 / rate);
  int64_t next = monotonic_ns();
  auto drain = [&](int ms) {
    for (int64_t end = monotonic_ns() + int64_t{ms} * 1'000'000; monotonic_ns() < end;) {
      Result<std::optional<listen::Message>> m = client->next(5);
      if (!m.ok() || !m.value()) continue;
      auto f = m.value()->frame_prediction();
      if (!f.ok()) continue;
      if (!testing::fixture_prediction_intact(f.value()))
        ++o.corrupted;
      else if (!seen.insert(f.value().frame_sequence()).second)
        ++o.duplicates;
      else
        ++o.intact;
    }
  };
  for (uint32_t n = 0; n < frames; ++n) {
    (void)sender->post(testing::fixture_prediction(n, st, n % 4 == 0));
    next += period;
    drain(static_cast<int>(std::max<int64_t>(0, (next - monotonic_ns()) / 1'000'000)));
  }
  drain(1500);
  sender->stop();
  const transport::SenderCounters sc = sender->counters();
  const listen::LinkStats ls = client->stats();
  const testing::PtyCable::Counts cc = cable.counts();
  o.sent = frames;
  o.bytes = cc.bytes, o.byte_errors = cc.corrupted, o.byte_drops = cc.dropped;
  o.rejected = ls.frames;
  o.gaps = ls.sequence_gaps, o.missing = ls.frames_missing;
  o.mean_wire_bytes =
      sc.frames_sent ? static_cast<double>(sc.bytes_sent) / static_cast<double>(sc.frames_sent) : 0;
  cable.unplug();
  ::rmdir(dir.c_str());
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  uint32_t frames = 3000;
  double rate = 1000;
  uint64_t seed = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--frames")
      frames = static_cast<uint32_t>(std::strtoul(argv[i + 1], nullptr, 10));
    else if (k == "--rate")
      rate = std::strtod(argv[i + 1], nullptr);
    else if (k == "--seed")
      seed = std::strtoull(argv[i + 1], nullptr, 10);
  }
  const Case cases[] = {{0, 0},    {1e-5, 0}, {1e-4, 0}, {1e-3, 0},    {1e-2, 0},   {0, 1e-5},
                        {0, 1e-4}, {0, 1e-3}, {0, 1e-2}, {1e-3, 1e-3}, {1e-2, 1e-2}};
  std::printf(
      "tlvlink corruption table: %u predictions per row at %.0f/s through a pty cable, seed %llu\n",
      frames, rate, static_cast<unsigned long long>(seed));
  std::printf(
      "(a quarter carry a 32-float embedding; errors replace a byte by a different random byte; "
      "drops delete it)\n\n");
  std::printf(
      "| byte error rate | byte drop rate | bytes damaged | frames sent | received intact | lost | "
      "expected lost | "
      "corrupted accepted | rejected (crc / cobs / truncated / length / other) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  bool ok = true;
  for (const Case& c : cases) {
    const Outcome o = run_case(c, frames, rate, seed);
    const uint64_t lost = o.sent - o.intact;
    // A frame survives when none of its wire bytes is hit: 1 - (1 - p)^L for its mean length L.
    const double p = c.error_rate + c.drop_rate;
    const double expected = static_cast<double>(o.sent) * (1 - std::pow(1 - p, o.mean_wire_bytes));
    const protocol::DeframerCounters& r = o.rejected;
    std::printf(
        "| %g | %g | %llu + %llu of %llu | %llu | %llu | %llu (%.2f %%) | %.0f | **%llu** | %llu / "
        "%llu / %llu / %llu / %llu |\n",
        c.error_rate, c.drop_rate, static_cast<unsigned long long>(o.byte_errors),
        static_cast<unsigned long long>(o.byte_drops), static_cast<unsigned long long>(o.bytes),
        static_cast<unsigned long long>(o.sent), static_cast<unsigned long long>(o.intact),
        static_cast<unsigned long long>(lost),
        100.0 * static_cast<double>(lost) / static_cast<double>(o.sent), expected,
        static_cast<unsigned long long>(o.corrupted), static_cast<unsigned long long>(r.crc),
        static_cast<unsigned long long>(r.cobs), static_cast<unsigned long long>(r.truncated),
        static_cast<unsigned long long>(r.length),
        static_cast<unsigned long long>(r.magic + r.version + r.flags + r.oversized));
    std::fflush(stdout);
    ok = ok && o.corrupted == 0;
  }
  std::printf("\n%s\n", ok ? "no corrupted frame was accepted" : "CORRUPTED FRAMES WERE ACCEPTED");
  return ok ? 0 : 1;
}
