#include "transport/test_host.h"

#include <cstring>

#include "tlvlink/protocol/encode.h"
#include "tlvlink/transport/serial.h"
#include "tlvlink/transport/time.h"

namespace tlvlink::testing {

TestHost::TestHost(std::string path)
    : path_(std::move(path)), deframer_(std::make_unique<protocol::Deframer>()) {}

Status TestHost::open() {
  TLV_ASSIGN_OR_RETURN(link_,
                       transport::make_serial_transport({path_, 0, transport::FlowControl::kNone}));
  disconnected = false;
  return link_->open();
}

void TestHost::close() {
  if (link_) link_->close();
  deframer_->reset();
}

bool TestHost::is_open() const { return link_ && link_->is_open(); }

void TestHost::pump(int ms, const std::function<bool()>& until) {
  const int64_t end = transport::monotonic_ns() + int64_t{ms} * 1'000'000;
  std::byte buf[4096];
  while (transport::monotonic_ns() < end) {
    if (until && until()) return;
    if (!is_open()) return;
    const int left = static_cast<int>((end - transport::monotonic_ns()) / 1'000'000);
    Result<transport::Readiness> r = link_->wait(false, left > 0 ? left : 1);
    if (!r.ok()) {
      disconnected = true;
      link_->close();
      return;
    }
    if (!r.value().readable) continue;
    Result<size_t> n = link_->read(buf);
    if (!n.ok()) {
      disconnected = true;
      link_->close();
      return;
    }
    const int64_t now = transport::monotonic_ns();
    deframer_->feed(
        std::span<const std::byte>(buf, n.value()), [&](const protocol::ReceivedFrame& f) {
          if (f.verdict != protocol::FrameVerdict::kOk) return;
          messages.push_back(
              Got{f.header, std::vector<std::byte>(f.payload.begin(), f.payload.end()), now});
        });
  }
}

Result<uint32_t> TestHost::send(const protocol::Command& command) {
  alignas(8) static std::byte scratch[protocol::kEncodeBufferSize];
  static std::byte wire[protocol::kMaxWireFrameSize];
  protocol::FrameHeader h;
  h.sequence = sequence_++;
  h.send_ns = transport::monotonic_ns();
  TLV_ASSIGN_OR_RETURN(const size_t n, protocol::encode_message(command, h, scratch, wire));
  TLV_TRY(send_raw(std::span<const std::byte>(wire, n)));
  return h.sequence;
}

Status TestHost::send_raw(std::span<const std::byte> bytes) {
  TLV_ENSURE(is_open(), ErrorCode::kInvalidState, "test host not open");
  size_t done = 0;
  for (int tries = 0; done < bytes.size() && tries < 1000; ++tries) {
    TLV_ASSIGN_OR_RETURN(const transport::Readiness r, link_->wait(true, 10));
    if (!r.writable) continue;
    TLV_ASSIGN_OR_RETURN(const size_t n, link_->write(bytes.subspan(done)));
    done += n;
  }
  TLV_ENSURE(done == bytes.size(), ErrorCode::kTransport, "test host: write stalled");
  return Status();
}

size_t TestHost::count(protocol::MessageType type) const {
  size_t n = 0;
  for (const Got& g : messages) n += g.header.type == type;
  return n;
}

const TestHost::Got* TestHost::last(protocol::MessageType type) const {
  for (auto it = messages.rbegin(); it != messages.rend(); ++it) {
    if (it->header.type == type) return &*it;
  }
  return nullptr;
}

AlignedPayload::AlignedPayload(std::span<const std::byte> p)
    : storage((p.size() + 7) / 8), size(p.size()) {
  if (size > 0) std::memcpy(storage.data(), p.data(), size);
}

std::span<const std::byte> AlignedPayload::bytes() const {
  return {reinterpret_cast<const std::byte*>(storage.data()), size};
}

}  // namespace tlvlink::testing
