// tlvlink_hil_relay: the host side of the board's prediction stream in the emulated board
// (tests/hil). The real C++ client (tools/listen) reads the stream — USB bulk through libusb and
// dummy_hcd, or CDC-ACM /dev/ttyACM0 — and records every byte it receives (flushed per read, so
// a relay killed mid-stream keeps what it had received) into a recording that the host decodes.
//   tlvlink_hil_relay --source SOURCE --record FILE [--timeout S] [--idle S] [--label NAME]
// Runs until SIGTERM, --timeout seconds, or --idle seconds without a prediction once one came.
// Prints one "relay-summary key=value ..." line: predictions, hellos, reconnects, rejected frames.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tlvlink/listen/client.h"
#include "tlvlink/transport/time.h"

namespace {

using namespace tlvlink;

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop = true; }

}  // namespace

int main(int argc, char** argv) {
  std::string source, record, label = "relay";
  double timeout_s = 120, idle_s = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const char* v = argv[i + 1];
    if (k == "--source")
      source = v;
    else if (k == "--record")
      record = v;
    else if (k == "--timeout")
      timeout_s = std::strtod(v, nullptr);
    else if (k == "--idle")
      idle_s = std::strtod(v, nullptr);
    else if (k == "--label")
      label = v;
    else
      source.clear(), i = argc;  // unknown option: usage below
  }
  if (source.empty() || record.empty() || argc % 2 == 0) {
    std::fprintf(stderr,
                 "usage: tlvlink_hil_relay --source SOURCE --record FILE [--timeout S] "
                 "[--idle S] [--label NAME]\n");
    return 2;
  }
  std::signal(SIGTERM, on_signal);
  std::signal(SIGINT, on_signal);
  listen::ClientOptions options;
  options.record = record;
  auto client = listen::Client::open(source, options);
  if (!client.ok()) {
    std::fprintf(stderr, "relay %s: %s\n", label.c_str(), client.error().message());
    return 1;
  }
  const int64_t start = transport::monotonic_ns();
  int64_t last_prediction = 0;
  uint64_t predictions = 0, hellos = 0;
  while (!g_stop) {
    const int64_t now = transport::monotonic_ns();
    if (now - start > static_cast<int64_t>(timeout_s * 1e9)) break;
    if (idle_s > 0 && last_prediction > 0 &&
        now - last_prediction > static_cast<int64_t>(idle_s * 1e9))
      break;
    auto m = (*client)->next(200);
    if (!m.ok()) {
      std::fprintf(stderr, "relay %s: %s\n", label.c_str(), m.error().message());
      return 1;
    }
    if (!m.value()) continue;
    if (m.value()->frame_prediction().ok()) {
      if (predictions == 0)  // CLOCK_MONOTONIC = the guest's uptime (no suspend in the rig)
        std::printf("relay %s: first prediction at uptime %.3f\n", label.c_str(),
                    static_cast<double>(transport::monotonic_ns()) * 1e-9);
      ++predictions;
      last_prediction = transport::monotonic_ns();
    } else if (m.value()->hello().ok()) {
      ++hellos;
    }
    for (const listen::LinkEvent& e : (*client)->take_events())
      std::printf("relay %s: %s %s\n", label.c_str(), listen::link_event_name(e.kind),
                  e.text.c_str());
    std::fflush(stdout);
  }
  const listen::LinkStats s = (*client)->stats();
  std::printf("relay-summary label=%s predictions=%llu hellos=%llu rejected=%llu missing=%llu\n",
              label.c_str(), static_cast<unsigned long long>(predictions),
              static_cast<unsigned long long>(hellos),
              static_cast<unsigned long long>(s.frames.rejected()),
              static_cast<unsigned long long>(s.frames_missing));
  return 0;
}
