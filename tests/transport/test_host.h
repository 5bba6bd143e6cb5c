#pragma once
// A minimal host for the transport tests (the real one is tools/listen): opens a serial path,
// deframes and keeps every good frame, sends commands. Everything runs on the calling thread.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tlvlink/protocol/deframer.h"
#include "tlvlink/protocol/messages.h"
#include "tlvlink/transport/transport.h"

namespace tlvlink::testing {

class TestHost {
 public:
  explicit TestHost(std::string path);
  Status open();
  void close();
  bool is_open() const;

  struct Got {
    protocol::FrameHeader header;
    std::vector<std::byte> payload;  // copy; 8-byte aligned storage is not needed by the views here
    int64_t received_ns = 0;
  };
  // Reads for up to `ms` or until `until()` is true (checked after every read).
  void pump(int ms, const std::function<bool()>& until = {});
  bool wait_for(int ms, const std::function<bool()>& until) {
    pump(ms, until);
    return until();
  }
  // Sends a command frame; returns its sequence number.
  Result<uint32_t> send(const protocol::Command& command);
  // Sends raw bytes (forged frames).
  Status send_raw(std::span<const std::byte> bytes);

  size_t count(protocol::MessageType type) const;
  const Got* last(protocol::MessageType type) const;
  std::vector<Got> messages;
  const protocol::DeframerCounters& counters() const { return deframer_->counters(); }
  bool disconnected = false;  // the link reported hangup since the last open()

 private:
  std::string path_;
  std::unique_ptr<transport::Transport> link_;
  std::unique_ptr<protocol::Deframer> deframer_;
  uint32_t sequence_ = 0;
};

// Copies a payload into 8-byte aligned storage for the decode_* views.
struct AlignedPayload {
  explicit AlignedPayload(std::span<const std::byte> p);
  std::span<const std::byte> bytes() const;
  std::vector<uint64_t> storage;
  size_t size;
};

}  // namespace tlvlink::testing
