#pragma once
// A Foxglove WebSocket server (https://github.com/foxglove/ws-protocol, subprotocol
// foxglove.websocket.v1) publishing the channel table (channels.h): a listener's messages, live.
// Foxglove (app or browser) connects to ws://HOST:PORT, sees the advertised channels and their
// JSON Schemas, subscribes and plots. Capabilities: none beyond subscribe / unsubscribe.
//
// The listener's thread only queues (a bounded queue per client, the oldest message dropped and
// counted when a client is slow); a websocketpp thread sends.

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "tlvlink/error.h"
#include "tlvlink/listen/session.h"

namespace tlvlink::foxglove {

namespace internal {
class WsServerCore;
}

struct HostPort {
  std::string host = "127.0.0.1";
  uint16_t port = 8765;
};
// "[HOST:]PORT": "8765", ":8765", "0.0.0.0:8765", "[::1]:8765"; PORT 0 picks a free port.
Result<HostPort> parse_host_port(std::string_view text);

struct ServerOptions {
  HostPort address;
  size_t queue_messages = 1024;  // per client, before the oldest is dropped
  std::string name = "tlvlink";  // serverInfo's name
};

struct ServerCounters {
  uint64_t clients = 0, messages_sent = 0, messages_dropped = 0, protocol_errors = 0;
};

class Server : public listen::MessageSink {
 public:
  // Binds and serves; an address in use or not local is an error naming it.
  static Result<std::unique_ptr<Server>> start(const ServerOptions& options);
  ~Server() override;  // shutdown()

  const std::string& address() const { return address_; }  // "HOST:PORT" as bound
  // Publishes the message on its channel (never fails, never waits for a client).
  Status on_message(const listen::Message& message, const listen::FormatContext& context) override;
  // Waits until one client is subscribed to every channel (true), or timeout / stop (false).
  bool wait_for_full_subscriber(int timeout_ms, const std::atomic<bool>& stop);
  ServerCounters counters() const;
  // Sends what is queued (at most drain_ms), unadvertises, closes every connection.
  void shutdown(int drain_ms = 2000);

 private:
  Server(std::unique_ptr<internal::WsServerCore> core, std::string address);
  std::unique_ptr<internal::WsServerCore> core_;
  std::string address_;
};

}  // namespace tlvlink::foxglove
