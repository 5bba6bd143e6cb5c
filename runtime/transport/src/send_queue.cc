#include "tlvlink/transport/send_queue.h"

#include <cstring>

namespace tlvlink::transport {
namespace {

// Record header: payload length (u32; kMarker = "the rest up to the end is unused, continue at
// 0"), type (u16), flags (u16), enqueue time (i64). Records never wrap around the end.
constexpr uint32_t kMarker = 0xFFFFFFFFu;

struct Header {
  uint32_t length;
  uint16_t type;
  uint16_t flags;
  int64_t enqueue_ns;
};
static_assert(sizeof(Header) == SendQueue::kRecordHeader);

}  // namespace

SendQueue::SendQueue(size_t capacity_bytes)
    : capacity_(capacity_bytes & ~size_t{15}),
      buffer_(new std::byte[capacity_ > 0 ? capacity_ : 16]) {}

bool SendQueue::is_marker(size_t offset) const {
  uint32_t length;
  std::memcpy(&length, buffer_.get() + offset, sizeof(length));
  return length == kMarker;
}

size_t SendQueue::size_at(size_t offset) const {
  uint32_t length;
  std::memcpy(&length, buffer_.get() + offset, sizeof(length));
  return record_size(length);
}

Result<size_t> SendQueue::push(protocol::MessageType type, uint16_t flags, int64_t enqueue_ns,
                               std::span<const std::byte> payload) {
  const size_t need = record_size(payload.size());
  TLV_ENSURE(need <= capacity_, ErrorCode::kProtocolTooLarge,
             "a %zu-byte message does not fit the %zu-byte send queue", payload.size(), capacity_);
  size_t dropped = 0;
  size_t at = 0;
  for (;;) {
    if (count_ == 0) {
      head_ = tail_ = 0;
      at = 0;
      break;
    }
    if (tail_ > head_) {  // used [head_, tail_): free at the end, then at the start
      if (capacity_ - tail_ >= need) {
        at = tail_;
        break;
      }
      if (head_ >= need) {
        if (capacity_ - tail_ >= kRecordHeader) {
          const Header marker{kMarker, 0, 0, 0};
          std::memcpy(buffer_.get() + tail_, &marker, sizeof(marker));
        }
        at = 0;
        break;
      }
    } else if (head_ - tail_ >= need) {  // wrapped: free [tail_, head_)
      at = tail_;
      break;
    }
    pop();
    ++dropped;
  }
  const Header header{static_cast<uint32_t>(payload.size()), static_cast<uint16_t>(type), flags,
                      enqueue_ns};
  std::memcpy(buffer_.get() + at, &header, sizeof(header));
  if (!payload.empty())
    std::memcpy(buffer_.get() + at + kRecordHeader, payload.data(), payload.size());
  tail_ = at + need;
  ++count_;
  bytes_ += need;
  return dropped;
}

bool SendQueue::front(Record& out) const {
  if (count_ == 0) return false;
  Header h;
  std::memcpy(&h, buffer_.get() + head_, sizeof(h));
  out.type = static_cast<protocol::MessageType>(h.type);
  out.flags = h.flags;
  out.enqueue_ns = h.enqueue_ns;
  out.payload = std::span<const std::byte>(buffer_.get() + head_ + kRecordHeader, h.length);
  return true;
}

void SendQueue::pop() {
  if (count_ == 0) return;
  const size_t n = size_at(head_);
  head_ += n;
  bytes_ -= n;
  if (--count_ == 0) {
    head_ = tail_ = 0;
    return;
  }
  if (head_ == capacity_ || is_marker(head_)) head_ = 0;
}

void SendQueue::clear() { head_ = tail_ = count_ = bytes_ = 0; }

}  // namespace tlvlink::transport
