#pragma once
// The board's bounded queue of encoded messages waiting for the link: one byte ring allocated
// at construction, records of (type, flags, enqueue time, payload). When a message does not
// fit, the oldest are dropped until it does (drop-oldest: the newest prediction is the useful
// one); push() says how many. Not thread-safe (the Sender locks it).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "tlvlink/error.h"
#include "tlvlink/protocol/wire.h"

namespace tlvlink::transport {

class SendQueue {
 public:
  static constexpr size_t kRecordHeader = 16;  // per message besides its payload (rounded to 16)

  // Capacity in bytes, rounded down to a multiple of 16.
  explicit SendQueue(size_t capacity_bytes);

  struct Record {
    protocol::MessageType type = protocol::MessageType::kHello;
    uint16_t flags = 0;
    int64_t enqueue_ns = 0;
    std::span<const std::byte> payload;  // valid until the next push() or pop()
  };

  // Appends a record, dropping the oldest ones until it fits; returns how many were dropped.
  // kProtocolTooLarge (and nothing dropped) when the record alone exceeds the capacity.
  Result<size_t> push(protocol::MessageType type, uint16_t flags, int64_t enqueue_ns,
                      std::span<const std::byte> payload);
  bool front(Record& out) const;  // false when empty
  void pop();
  void clear();

  size_t size() const { return count_; }
  size_t bytes() const { return bytes_; }  // in records, headers included
  size_t capacity() const { return capacity_; }
  // Bytes a record with this payload occupies.
  static size_t record_size(size_t payload_size) {
    return kRecordHeader + ((payload_size + 15) & ~size_t{15});
  }

 private:
  bool is_marker(size_t offset) const;
  size_t size_at(size_t offset) const;
  size_t capacity_;
  std::unique_ptr<std::byte[]> buffer_;
  size_t head_ = 0, tail_ = 0, count_ = 0, bytes_ = 0;
};

}  // namespace tlvlink::transport
