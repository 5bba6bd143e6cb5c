#pragma once
// A pseudo-terminal whose master side is the transport and whose slave side a reader opens like
// a serial port (`tlvlink listen --serial LINK`, pyserial). For tests and for a daemon run on a
// development host ("the stream over a pty"). open() creates the pair and, if `link` is set,
// points that symlink at the slave (/dev/pts/N). While no reader has the slave open the master
// reports hangup: peer_present() is false and the sender keeps what it would send; a reader
// that comes back (or a new one) gets it, including what the kernel still buffered.

#include <memory>
#include <string>

#include "tlvlink/error.h"
#include "tlvlink/transport/transport.h"

namespace tlvlink::transport {

struct PtyConfig {
  std::string link;  // symlink to the slave, replaced atomically; empty: none
};

// kInvalidArgument unless `link` is absent or a symlink to a /dev/pts slave (left by an earlier
// run): open() never replaces a regular file or anything else that happens to be at that path.
Status check_pty_link(const std::string& link);

class PtyTransport final : public Transport {
 public:
  explicit PtyTransport(PtyConfig config);
  ~PtyTransport() override;
  PtyTransport(const PtyTransport&) = delete;
  PtyTransport& operator=(const PtyTransport&) = delete;

  std::string_view name() const override { return name_; }
  Status open() override;
  void close() override;
  bool is_open() const override { return master_ >= 0; }
  Result<Readiness> wait(bool want_write, int timeout_ms) override;
  Result<size_t> read(std::span<std::byte> out) override;
  Result<size_t> write(std::span<const std::byte> data) override;
  void interrupt() override;
  void drain(int timeout_ms) override;
  bool peer_present() const override { return peer_present_; }

  const std::string& slave_path() const { return slave_path_; }  // /dev/pts/N while open

 private:
  PtyConfig config_;
  std::string name_, slave_path_;
  int master_ = -1, wake_ = -1;
  bool peer_present_ = false;
};

}  // namespace tlvlink::transport
