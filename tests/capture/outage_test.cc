// The outage loop the V4L2 and libcamera sources share (tlvlink/capture/outage.h), on a
// FakeClock: each call waits exactly its timeout, reopen attempts follow the doubling backoff,
// the outage's length is counted, and the error names the attempts and the last reopen error.
#include "tlvlink/capture/outage.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/clock.h"

namespace tlvlink::capture {
namespace {

struct Device {
  ReconnectBackoff backoff{20, 160};
  SourceStats stats;
  Error last_error;
  OutageBook book() { return {backoff, stats, last_error}; }
  std::vector<int64_t> attempts_ms;  // board clock of each reopen attempt, from the loss
  int64_t lost_at = 0;
  int fail_first = 1 << 30;  // attempts that fail before one succeeds
  Status reopen() {
    attempts_ms.push_back((board_clock_ns() - lost_at) / kNsPerMs);
    if (static_cast<int>(attempts_ms.size()) <= fail_first)
      return Error::make(ErrorCode::kCaptureNoDevice, "no camera matches");
    return Status();
  }
};

TEST(Outage, EachCallWaitsItsTimeoutAndAttemptsFollowTheBackoff) {
  FakeClock clock(10 * kNsPerS);
  Device d;
  d.lost_at = board_clock_ns();
  begin_outage(d.book(), /*streamed=*/true);
  EXPECT_EQ(d.stats.disconnects, 1u);
  auto reopen = [&d] { return d.reopen(); };
  Status last;
  for (int i = 0; i < 12; ++i) {
    const int64_t t0 = board_clock_ns();
    last = reconnect_until(d.book(), "cam", t0 + 100 * kNsPerMs, reopen);
    ASSERT_FALSE(last.ok());
    EXPECT_EQ(last.error().code(), ErrorCode::kCaptureDisconnected);
    EXPECT_EQ(board_clock_ns() - t0, 100 * kNsPerMs) << "call " << i << " did not wait its timeout";
  }
  // The first attempt one delay after the loss, then the delay doubles up to 160 ms.
  EXPECT_EQ(d.attempts_ms, (std::vector<int64_t>{20, 60, 140, 300, 460, 620, 780, 940, 1100}));
  EXPECT_EQ(d.stats.reconnect_attempts, 9u);
  EXPECT_EQ(d.stats.outage_ns, 1200 * kNsPerMs);
  const std::string message = last.error().message();
  EXPECT_NE(message.find("cam: disconnected for 1200 ms, 9 reopen attempts failed, next in 60 ms"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("no camera matches"), std::string::npos) << message;
}

TEST(Outage, ReopenedEndsTheOutageAndStopKeepsItsLength) {
  FakeClock clock(kNsPerS);
  Device d;
  d.fail_first = 2;
  d.lost_at = board_clock_ns();
  begin_outage(d.book(), true);
  auto reopen = [&d] { return d.reopen(); };
  const Status st = reconnect_until(d.book(), "cam", board_clock_ns() + kNsPerS, reopen);
  ASSERT_TRUE(st.ok()) << st.error().message();
  EXPECT_EQ(d.attempts_ms, (std::vector<int64_t>{20, 60, 140}));
  EXPECT_EQ(d.stats.reconnects, 1u);
  EXPECT_EQ(d.stats.outage_ns, 140 * kNsPerMs);
  EXPECT_FALSE(d.backoff.in_outage());
  // A second outage, stopped while it lasts: its time so far is added.
  begin_outage(d.book(), false);
  clock.advance_ms(50);
  end_outage_at_stop(d.book());
  EXPECT_EQ(d.stats.outage_ns, 190 * kNsPerMs);
  EXPECT_EQ(d.stats.disconnects, 2u);
}

TEST(Outage, BeforeAnyAttemptTheErrorSaysSo) {
  FakeClock clock(kNsPerS);
  Device d;
  begin_outage(d.book(), true);
  auto reopen = [&d] { return d.reopen(); };
  const Status st = reconnect_until(d.book(), "cam", board_clock_ns(), reopen);  // timeout 0
  ASSERT_FALSE(st.ok());
  EXPECT_TRUE(d.attempts_ms.empty());
  EXPECT_NE(std::string(st.error().message()).find("not reopened yet"), std::string::npos);
}

}  // namespace
}  // namespace tlvlink::capture
