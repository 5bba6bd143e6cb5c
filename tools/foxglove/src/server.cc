#include "tlvlink/foxglove/server.h"

#include <charconv>

#include "tlvlink/foxglove/channels.h"
#include "ws_server_core.h"

namespace tlvlink::foxglove {

Result<HostPort> parse_host_port(std::string_view text) {
  HostPort out;
  std::string_view port = text;
  if (const size_t colon = text.rfind(':'); colon != std::string_view::npos) {
    std::string_view host = text.substr(0, colon);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']')
      host = host.substr(1, host.size() - 2);
    if (!host.empty()) out.host = std::string(host);
    port = text.substr(colon + 1);
  }
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  TLV_ENSURE(
      !port.empty() && ec == std::errc() && end == port.data() + port.size() && value <= 65535,
      ErrorCode::kInvalidArgument,
      "foxglove address '%.*s': expected [HOST:]PORT with PORT 0..65535",
      static_cast<int>(text.size()), text.data());
  out.port = static_cast<uint16_t>(value);
  return out;
}

Server::Server(std::unique_ptr<internal::WsServerCore> core, std::string address)
    : core_(std::move(core)), address_(std::move(address)) {}

Server::~Server() { shutdown(); }

Result<std::unique_ptr<Server>> Server::start(const ServerOptions& options) {
  std::vector<internal::WsChannel> channels;
  for (const ChannelSpec& c : channel_table()) {
    // The Hello comes once per connect: a client that subscribes later still gets the board's.
    channels.push_back({c.id, std::string(c.topic), std::string(kMessageEncoding),
                        std::string(c.schema_name), std::string(c.schema),
                        std::string(kSchemaEncoding), c.topic == "/tlvlink/hello"});
  }
  std::string error;
  std::unique_ptr<internal::WsServerCore> core =
      internal::WsServerCore::start(options.address.host, options.address.port, std::move(channels),
                                    options.queue_messages, options.name, &error);
  TLV_ENSURE(core != nullptr, ErrorCode::kTransport, "foxglove: %s", error.c_str());
  std::string address = core->address();
  return std::unique_ptr<Server>(new Server(std::move(core), std::move(address)));
}

Status Server::on_message(const listen::Message& message, const listen::FormatContext& context) {
  if (std::optional<ChannelMessage> m = to_channel_message(message, context)) {
    core_->publish(m->channel_id, static_cast<uint64_t>(m->log_time_ns), m->json);
  }
  return Status();
}

bool Server::wait_for_full_subscriber(int timeout_ms, const std::atomic<bool>& stop) {
  return core_->wait_for_full_subscriber(timeout_ms, &stop);
}

ServerCounters Server::counters() const {
  const internal::WsCounters c = core_->counters();
  return {c.clients, c.messages_sent, c.messages_dropped, c.protocol_errors};
}

void Server::shutdown(int drain_ms) {
  if (core_) core_->shutdown(drain_ms);
}

}  // namespace tlvlink::foxglove
