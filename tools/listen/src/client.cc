// listen::Client: opening a source, the public API over the live and replay pumps.
#include "tlvlink/listen/client.h"

#include "client_impl.h"
#include "tlvlink/listen/usb_host.h"
#include "tlvlink/protocol/encode.h"
#include "tlvlink/transport/time.h"
#include "tlvlink/transport/transport_spec.h"

namespace tlvlink::listen {

using transport::monotonic_ns;

const char* link_event_name(LinkEvent::Kind kind) {
  switch (kind) {
    case LinkEvent::Kind::kConnected: return "connected";
    case LinkEvent::Kind::kDisconnected: return "disconnected";
    case LinkEvent::Kind::kVersionMismatch: return "version_mismatch";
    case LinkEvent::Kind::kBoardRestarted: return "board_restarted";
    case LinkEvent::Kind::kEndOfRecording: return "end_of_recording";
  }
  return "unknown";
}

Client::Client(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Client::~Client() {
  if (impl_->link) impl_->link->close();
  if (impl_->recorder) (void)impl_->recorder->flush();
}

Result<std::unique_ptr<Client>> Client::open(std::string_view source,
                                             const ClientOptions& options) {
  auto impl = std::make_unique<Impl>();
  impl->source = std::string(source);
  impl->options = options;
  impl->backoff_ms = options.reconnect_min_ms;
  TLV_ENSURE(options.reconnect_min_ms > 0 && options.reconnect_max_ms >= options.reconnect_min_ms &&
                 options.time_sync_ms >= 0,
             ErrorCode::kInvalidArgument, "client: reconnect/time-sync periods out of range");
  const std::string_view scheme = source.substr(0, std::min(source.find(':'), source.find(',')));
  if (scheme == "serial") {
    TLV_ASSIGN_OR_RETURN(impl->link, transport::make_transport(source));
  } else if (scheme == "usb") {
    const size_t skip = source.size() > 3 && source[3] == ':' ? 4 : 3;
    TLV_ASSIGN_OR_RETURN(const UsbSelector selector, parse_usb_selector(source.substr(skip)));
    TLV_ASSIGN_OR_RETURN(impl->link, make_usb_host_transport(selector));
  } else if (scheme == "replay") {
    TLV_ENSURE(source.size() > 7, ErrorCode::kInvalidArgument,
               "replay: needs a file (replay:FILE)");
    TLV_ASSIGN_OR_RETURN(impl->replay, RecordingReader::open(std::string(source.substr(7))));
    impl->sent_deframer = std::make_unique<protocol::Deframer>();
  } else {
    return Error::make(
        ErrorCode::kInvalidArgument,
        "source '%.*s': expected serial:PATH[,baud=N][,flow=rtscts], usb[:VID:PID][,serial=S] or "
        "replay:FILE",
        static_cast<int>(source.size()), source.data());
  }
  if (!options.record.empty()) {
    TLV_ENSURE(impl->replay == nullptr, ErrorCode::kInvalidArgument,
               "--record with a replay: copy the file instead");
    TLV_ASSIGN_OR_RETURN(impl->recorder,
                         RecordingWriter::create(options.record, options.overwrite_record));
  }
  impl->sink = options.record_sink;
  return std::unique_ptr<Client>(new Client(std::move(impl)));
}

Result<std::unique_ptr<Client>> Client::open_replay(std::unique_ptr<RecordSource> records,
                                                    std::string name,
                                                    const ClientOptions& options) {
  TLV_ENSURE(records != nullptr, ErrorCode::kInvalidArgument, "replay %s: no records",
             name.c_str());
  TLV_ENSURE(options.record.empty(), ErrorCode::kInvalidArgument,
             "--record with a replay: copy the file instead");
  auto impl = std::make_unique<Impl>();
  impl->source = std::move(name);
  impl->options = options;
  impl->replay = std::move(records);
  impl->sent_deframer = std::make_unique<protocol::Deframer>();
  impl->sink = options.record_sink;
  return std::unique_ptr<Client>(new Client(std::move(impl)));
}

Result<std::optional<Message>> Client::next(int timeout_ms) {
  Impl& s = *impl_;
  if (s.ready.empty() && !s.ended) {
    const int64_t deadline = monotonic_ns() + int64_t{std::max(timeout_ms, 0)} * 1'000'000;
    TLV_TRY(s.replay ? s.pump_replay(deadline) : s.pump_live(deadline));
  }
  // A recording that can no longer be written (disk full, file-size limit) ends the session:
  // going on would keep printing while the record the user asked for is silently incomplete.
  if (s.record_error) return *s.record_error;
  if (s.ready.empty()) return std::optional<Message>();
  std::optional<Message> m(std::move(s.ready.front()));
  s.ready.pop_front();
  return m;
}

Status Client::run(const Handlers& handlers, const std::atomic<bool>* stop, int64_t duration_ms) {
  const int64_t end = duration_ms < 0 ? INT64_MAX : monotonic_ns() + duration_ms * 1'000'000;
  for (;;) {
    const int64_t now = monotonic_ns();
    const int step_ms =
        static_cast<int>(std::min<int64_t>(100, std::max<int64_t>(0, (end - now) / 1'000'000)));
    Result<std::optional<Message>> m = next(step_ms);
    for (const LinkEvent& e : take_events()) {
      if (handlers.on_event) handlers.on_event(e);
    }
    if (!m.ok()) return m.error();
    if (m.value() && handlers.on_message) handlers.on_message(*m.value());
    if (impl_->ended && impl_->ready.empty()) return Status();
    if ((stop && stop->load()) || monotonic_ns() >= end) return Status();
  }
}

std::vector<LinkEvent> Client::take_events() {
  std::lock_guard lock(impl_->mutex);
  std::vector<LinkEvent> out;
  out.swap(impl_->events);
  return out;
}

Result<uint32_t> Client::send(const protocol::Command& command) {
  Impl& s = *impl_;
  TLV_ENSURE(s.link != nullptr, ErrorCode::kInvalidState, "a recording cannot take commands");
  alignas(8) static thread_local std::byte scratch[protocol::kEncodeBufferSize];
  static thread_local std::byte wire[protocol::kMaxWireFrameSize];
  {
    std::lock_guard lock(s.mutex);
    TLV_ENSURE(s.stats.link_up, ErrorCode::kTransportUnavailable, "%s is not connected%s%s",
               s.source.c_str(), s.down_reason.empty() ? "" : ": ", s.down_reason.c_str());
    protocol::FrameHeader h;
    h.sequence = s.next_sequence++;
    h.send_ns = monotonic_ns();
    TLV_ASSIGN_OR_RETURN(const size_t n, protocol::encode_message(command, h, scratch, wire));
    s.out_user.insert(s.out_user.end(), wire, wire + n);
    s.note_sent(h.sequence, h.send_ns);
    s.link->interrupt();
    return h.sequence;
  }
}

bool Client::ended() const { return impl_->ended && impl_->ready.empty(); }

LinkStats Client::stats() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->stats;
}

protocol::ClockEstimate Client::clock() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->clock.estimate(monotonic_ns());
}

int64_t Client::board_to_host_ns(int64_t board_ns) const {
  std::lock_guard lock(impl_->mutex);
  return impl_->clock.board_to_host(board_ns);
}

int64_t Client::host_to_board_ns(int64_t host_ns) const {
  std::lock_guard lock(impl_->mutex);
  return impl_->clock.host_to_board(host_ns);
}

std::optional<Message> Client::hello() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->hello;
}

std::string_view Client::source() const { return impl_->source; }

}  // namespace tlvlink::listen
