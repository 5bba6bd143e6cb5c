#pragma once
// A Transport that damages what it writes before it reaches the link: bytes are dropped or
// replaced at stated rates (byte_faults.h) between the Sender and the real transport, so the
// damaged stream crosses the real wire (the FunctionFS gadget and dummy_hcd, a CDC-ACM pair) and
// the host's decoder sees exactly what a noisy link would deliver. Reading is untouched. Used by
// `tlvlink_stream_check board --byte-errors P --byte-drops Q` (tools/listen/bench) in the
// emulated board; the pty tests damage the bytes in PtyCable instead.
//
// Bytes accepted by write() are damaged into a staging buffer at once and handed to the inner
// transport as it takes them; a disconnect discards what was staged (bytes in flight on a
// link that went away). No allocation after construction.

#include <cstddef>
#include <memory>
#include <mutex>
#include <string>

#include "byte_faults.h"
#include "tlvlink/transport/transport.h"

namespace tlvlink::testing {

class CorruptingTransport final : public transport::Transport {
 public:
  CorruptingTransport(std::unique_ptr<transport::Transport> inner, ByteFaultRates rates);

  std::string_view name() const override { return name_; }
  Status open() override;
  void close() override;
  bool is_open() const override { return inner_->is_open(); }
  Result<transport::Readiness> wait(bool want_write, int timeout_ms) override;
  Result<size_t> read(std::span<std::byte> out) override { return inner_->read(out); }
  Result<size_t> write(std::span<const std::byte> data) override;
  void interrupt() override { inner_->interrupt(); }
  void drain(int timeout_ms) override;
  bool peer_present() const override { return inner_->peer_present(); }

  // Thread-safe (the link thread updates them).
  ByteFaultCounts counts() const;

 private:
  Status flush();  // staged bytes to the inner transport, as many as it takes now

  std::unique_ptr<transport::Transport> inner_;
  std::string name_;
  ByteFaults faults_;
  mutable std::mutex mutex_;  // guards faults_' counts for counts()
  std::byte staged_[4096];
  size_t staged_len_ = 0, staged_pos_ = 0;
};

}  // namespace tlvlink::testing
