#pragma once
// A serial "cable" for tests: two pty pairs joined by a relay thread. The board side opens
// board_path(), the host side host_path() (symlinks to the two slaves, like /dev/ttyGS0 and
// /dev/ttyACM0). Bytes from board to host can be corrupted (a byte replaced by a different
// random one) or dropped at stated rates, from a seeded generator. unplug() removes both ends
// (each side sees a hangup and its path disappears); plug() brings new ones at the same paths.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "byte_faults.h"
#include "tlvlink/error.h"

namespace tlvlink::testing {

class PtyCable {
 public:
  using Faults = ByteFaultRates;   // per byte, board -> host (byte_faults.h)
  using Counts = ByteFaultCounts;  // board -> host

  explicit PtyCable(std::string dir);
  PtyCable(std::string dir, Faults faults);
  ~PtyCable();
  PtyCable(const PtyCable&) = delete;
  PtyCable& operator=(const PtyCable&) = delete;

  Status plug();
  void unplug();
  std::string board_path() const { return dir_ + "/board-tty"; }
  std::string host_path() const { return dir_ + "/host-tty"; }
  Counts counts() const;

 private:
  void relay();
  std::string dir_;
  Faults faults_;
  int board_master_ = -1, host_master_ = -1, stop_fd_ = -1;
  std::thread thread_;
  std::atomic<bool> running_{false};
  mutable std::mutex mutex_;
  Counts counts_;
};

}  // namespace tlvlink::testing
