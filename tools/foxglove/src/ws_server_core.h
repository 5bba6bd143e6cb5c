#pragma once
// The Foxglove WebSocket protocol server (subprotocol foxglove.websocket.v1) on websocketpp:
// serverInfo and advertise on connect, subscribe / unsubscribe, binary messageData (opcode 1,
// subscription id u32, timestamp u64, payload), unadvertise before closing. Internal to
// tlvlink_foxglove and compiled as C++17 with no tlvlink header: websocketpp 0.8 does not
// compile as C++20.
//
// Threading: one io thread runs websocketpp. publish() (the listener's thread) only appends to
// each subscribed client's bounded queue under a mutex and wakes the io thread; a slow client's
// oldest queued messages are dropped and counted, so the listener never waits for a client.
#ifndef TLVLINK_FOXGLOVE_PRIVATE
#error "ws_server_core.h is internal to tlvlink_foxglove"
#endif

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace tlvlink::foxglove::internal {

struct WsChannel {
  uint32_t id;
  std::string topic, encoding, schema_name, schema, schema_encoding;
  bool latched = false;  // a new subscriber gets the last message at once (the board's Hello)
};

struct WsCounters {
  uint64_t clients = 0;           // connections accepted so far
  uint64_t messages_sent = 0;     // messageData frames handed to websocketpp
  uint64_t messages_dropped = 0;  // dropped from slow clients' queues (oldest first)
  uint64_t protocol_errors = 0;   // client requests answered with an error status
};

class WsServerCore {
 public:
  // Binds HOST:PORT (port 0: any free port) and serves on a thread. nullptr and *error on failure.
  static std::unique_ptr<WsServerCore> start(const std::string& host, uint16_t port,
                                             std::vector<WsChannel> channels, size_t queue_limit,
                                             const std::string& name, std::string* error);
  ~WsServerCore();
  WsServerCore(const WsServerCore&) = delete;
  WsServerCore& operator=(const WsServerCore&) = delete;

  std::string address() const;  // "HOST:PORT" as bound
  // Queues the message for every client subscribed to the channel; never blocks on a client.
  void publish(uint32_t channel_id, uint64_t timestamp_ns, const std::string& payload);
  // Waits until one client is subscribed to every channel (true), or timeout / *stop (false).
  bool wait_for_full_subscriber(int timeout_ms, const std::atomic<bool>* stop);
  WsCounters counters() const;
  // Sends what the clients' queues hold (waiting at most drain_ms), unadvertises every channel,
  // closes the connections and stops the io thread.
  void shutdown(int drain_ms);

 private:
  struct Impl;
  explicit WsServerCore(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace tlvlink::foxglove::internal
