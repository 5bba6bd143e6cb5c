// websocketpp (Debian's libwebsocketpp-dev, standalone asio from libasio-dev) serving the
// Foxglove WebSocket protocol. C++17: see ws_server_core.h.
#include "ws_server_core.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

namespace tlvlink::foxglove::internal {
namespace {

using Server = websocketpp::server<websocketpp::config::asio>;
using Hdl = websocketpp::connection_hdl;
using nlohmann::json;

constexpr const char* kSubprotocol = "foxglove.websocket.v1";
// websocketpp's own buffer per client: beyond this, messages wait in our bounded queue.
constexpr size_t kMaxBufferedBytes = 1 << 20;

std::string message_data(uint32_t subscription, uint64_t timestamp_ns, const std::string& payload) {
  std::string frame(1 + 4 + 8, '\0');
  frame[0] = 1;  // messageData
  for (int i = 0; i < 4; ++i) frame[1 + i] = static_cast<char>((subscription >> (8 * i)) & 0xFF);
  for (int i = 0; i < 8; ++i) frame[5 + i] = static_cast<char>((timestamp_ns >> (8 * i)) & 0xFF);
  return frame + payload;
}

struct Client {
  std::map<uint32_t, uint32_t> subscriptions;  // subscription id -> channel id
  std::deque<std::string> queue;               // messageData frames waiting for websocketpp
};

std::string status(int level, const std::string& message) {
  return json{{"op", "status"}, {"level", level}, {"message", message}}.dump();
}

}  // namespace

struct WsServerCore::Impl {
  Server server;
  std::thread thread;
  std::vector<WsChannel> channels;
  size_t queue_limit = 0;
  std::string name, address;
  std::unique_ptr<asio::steady_timer> retry;

  mutable std::mutex mutex;  // guards clients and counters (publish() runs on another thread)
  std::condition_variable subscribed;
  std::map<Hdl, Client, std::owner_less<Hdl>> clients;
  std::map<uint32_t, std::pair<uint64_t, std::string>> last;  // latched channel -> its last message
  WsCounters counters;
  bool flush_posted = false, draining = false, closed = false;
  std::condition_variable drained;

  bool has_channel(uint32_t id) const {
    for (const WsChannel& c : channels) {
      if (c.id == id) return true;
    }
    return false;
  }

  void send_text(Hdl h, const std::string& text) {
    websocketpp::lib::error_code ec;
    server.send(h, text, websocketpp::frame::opcode::text, ec);
  }

  void on_open(Hdl h) {
    json info = {{"op", "serverInfo"},
                 {"name", name},
                 {"capabilities", json::array()},
                 {"supportedEncodings", json::array()},
                 {"metadata", json::object()}};
    json advertise = {{"op", "advertise"}, {"channels", json::array()}};
    for (const WsChannel& c : channels) {
      advertise["channels"].push_back({{"id", c.id},
                                       {"topic", c.topic},
                                       {"encoding", c.encoding},
                                       {"schemaName", c.schema_name},
                                       {"schema", c.schema},
                                       {"schemaEncoding", c.schema_encoding}});
    }
    {
      std::lock_guard lock(mutex);
      clients[h];
      ++counters.clients;
    }
    send_text(h, info.dump());
    send_text(h, advertise.dump());
  }

  void on_close(Hdl h) {
    std::lock_guard lock(mutex);
    clients.erase(h);
    drained.notify_all();
  }

  // Client requests: subscribe and unsubscribe; anything else is answered with an error status.
  void on_message(Hdl h, Server::message_ptr msg) {
    std::string problem;
    if (msg->get_opcode() != websocketpp::frame::opcode::text) {
      problem = "binary client messages are not supported by this server";
    } else {
      problem = handle(h, msg->get_payload());
    }
    if (!problem.empty()) {
      {
        std::lock_guard lock(mutex);
        ++counters.protocol_errors;
      }
      send_text(h, status(2, problem));
    }
  }

  std::string handle(Hdl h, const std::string& text) {
    const json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (!j.is_object() || !j.contains("op") || !j["op"].is_string())
      return "a client message must be a JSON object with \"op\"";
    const std::string op = j["op"];
    std::lock_guard lock(mutex);
    auto client = clients.find(h);
    if (client == clients.end()) return "unknown connection";
    if (op == "subscribe") {
      if (!j.contains("subscriptions") || !j["subscriptions"].is_array())
        return "subscribe: no \"subscriptions\" array";
      for (const json& s : j["subscriptions"]) {
        if (!s.is_object() || !s.contains("id") || !s["id"].is_number_unsigned() ||
            !s.contains("channelId") || !s["channelId"].is_number_unsigned()) {
          return "subscribe: each subscription needs unsigned \"id\" and \"channelId\"";
        }
        const uint32_t id = s["id"], channel = s["channelId"];
        if (!has_channel(channel)) return "subscribe: no channel " + std::to_string(channel);
        if (client->second.subscriptions.count(id))
          return "subscribe: subscription id " + std::to_string(id) + " is in use";
        client->second.subscriptions[id] = channel;
        if (auto l = last.find(channel); l != last.end()) {
          client->second.queue.push_back(message_data(id, l->second.first, l->second.second));
          if (!flush_posted) {
            flush_posted = true;
            asio::post(server.get_io_service(), [this] { flush(); });
          }
        }
      }
      subscribed.notify_all();
      return "";
    }
    if (op == "unsubscribe") {
      if (!j.contains("subscriptionIds") || !j["subscriptionIds"].is_array())
        return "unsubscribe: no \"subscriptionIds\" array";
      for (const json& id : j["subscriptionIds"]) {
        if (id.is_number_unsigned()) client->second.subscriptions.erase(id.get<uint32_t>());
      }
      return "";
    }
    return "unsupported operation '" + op + "' (this server offers subscribe and unsubscribe)";
  }

  // On the io thread: hands queued frames to websocketpp while its buffer has room; retries soon
  // when a client is still behind. When draining and everything went out, unadvertises and
  // closes. The frames are taken under the mutex and sent after it: publish() waits for a few
  // pointer moves, never for websocketpp's copying.
  void flush() {
    std::vector<std::pair<Hdl, std::string>> out;
    {
      std::lock_guard lock(mutex);
      flush_posted = false;
      for (auto& [h, c] : clients) {
        websocketpp::lib::error_code ec;
        Server::connection_ptr con = server.get_con_from_hdl(h, ec);
        if (ec) continue;
        size_t room = kMaxBufferedBytes - std::min(kMaxBufferedBytes, con->get_buffered_amount());
        while (!c.queue.empty() && room > 0) {
          room -= std::min(room, c.queue.front().size());
          out.emplace_back(h, std::move(c.queue.front()));
          c.queue.pop_front();
          ++counters.messages_sent;
        }
      }
    }
    for (auto& [h, frame] : out) {
      websocketpp::lib::error_code ec;
      server.send(h, frame, websocketpp::frame::opcode::binary, ec);
    }
    std::unique_lock lock(mutex);
    bool behind = false;
    for (auto& [h, c] : clients) {
      websocketpp::lib::error_code ec;
      Server::connection_ptr con = server.get_con_from_hdl(h, ec);
      if (!ec) behind = behind || !c.queue.empty() || con->get_buffered_amount() > 0;
    }
    if (draining && !behind) {
      finish(lock);
      return;
    }
    if (behind || draining) {
      retry->expires_after(std::chrono::milliseconds(2));
      retry->async_wait([this](const asio::error_code& e) {
        if (!e) flush();
      });
    }
  }

  // Unadvertise and close every connection, stop accepting; the io thread then runs out of work.
  void finish(std::unique_lock<std::mutex>& lock) {
    if (closed) return;
    closed = true;
    json ids = json::array();
    for (const WsChannel& c : channels) ids.push_back(c.id);
    const std::string unadvertise = json{{"op", "unadvertise"}, {"channelIds", ids}}.dump();
    std::vector<Hdl> open;
    for (auto& [h, c] : clients) open.push_back(h);
    lock.unlock();
    websocketpp::lib::error_code ec;
    server.stop_listening(ec);
    for (Hdl h : open) {
      send_text(h, unadvertise);
      server.close(h, websocketpp::close::status::going_away, "server shutting down", ec);
    }
    lock.lock();
    drained.notify_all();
  }
};

WsServerCore::WsServerCore(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

WsServerCore::~WsServerCore() { shutdown(0); }

std::unique_ptr<WsServerCore> WsServerCore::start(const std::string& host, uint16_t port,
                                                  std::vector<WsChannel> channels,
                                                  size_t queue_limit, const std::string& name,
                                                  std::string* error) {
  auto impl = std::make_unique<Impl>();
  Impl& s = *impl;
  s.channels = std::move(channels);
  s.queue_limit = queue_limit == 0 ? 1 : queue_limit;
  s.name = name;
  try {
    s.server.clear_access_channels(websocketpp::log::alevel::all);
    s.server.clear_error_channels(websocketpp::log::elevel::all);
    s.server.init_asio();
    s.server.set_reuse_addr(true);
    s.retry = std::make_unique<asio::steady_timer>(s.server.get_io_service());
    // Only clients that speak foxglove.websocket.v1 are accepted (the protocol's handshake).
    s.server.set_validate_handler([&s](Hdl h) {
      Server::connection_ptr con = s.server.get_con_from_hdl(h);
      for (const std::string& p : con->get_requested_subprotocols()) {
        if (p == kSubprotocol) {
          con->select_subprotocol(kSubprotocol);
          return true;
        }
      }
      con->set_status(websocketpp::http::status_code::bad_request);
      con->set_body(std::string("this server speaks the WebSocket subprotocol ") + kSubprotocol +
                    "\n");
      return false;
    });
    s.server.set_open_handler([&s](Hdl h) { s.on_open(h); });
    s.server.set_close_handler([&s](Hdl h) { s.on_close(h); });
    s.server.set_fail_handler([&s](Hdl h) { s.on_close(h); });
    s.server.set_message_handler([&s](Hdl h, Server::message_ptr m) { s.on_message(h, m); });
    s.server.listen(host, std::to_string(port));
    asio::error_code ec;
    const asio::ip::tcp::endpoint bound = s.server.get_local_endpoint(ec);
    if (ec) throw websocketpp::exception(ec.message());
    const std::string ip = bound.address().to_string();
    s.address =
        (bound.address().is_v6() ? "[" + ip + "]" : ip) + ":" + std::to_string(bound.port());
    s.server.start_accept();
  } catch (const std::exception& e) {
    *error = "cannot serve on " + host + ":" + std::to_string(port) + ": " + e.what();
    return nullptr;
  }
  s.thread = std::thread([&s] {
    try {
      s.server.run();
    } catch (const std::exception&) {
      // The io loop ended on an error; publish() only queues, shutdown() still returns.
    }
  });
  return std::unique_ptr<WsServerCore>(new WsServerCore(std::move(impl)));
}

std::string WsServerCore::address() const { return impl_->address; }

void WsServerCore::publish(uint32_t channel_id, uint64_t timestamp_ns, const std::string& payload) {
  Impl& s = *impl_;
  bool post = false;
  {
    std::lock_guard lock(s.mutex);
    if (s.draining) return;
    for (const WsChannel& ch : s.channels) {
      if (ch.id == channel_id && ch.latched) s.last[channel_id] = {timestamp_ns, payload};
    }
    for (auto& [h, c] : s.clients) {
      for (const auto& [sub, channel] : c.subscriptions) {
        if (channel != channel_id) continue;
        c.queue.push_back(message_data(sub, timestamp_ns, payload));
        if (c.queue.size() > s.queue_limit) {
          c.queue.pop_front();
          ++s.counters.messages_dropped;
        }
        post = true;
      }
    }
    post = post && !s.flush_posted;
    if (post) s.flush_posted = true;
  }
  if (post) asio::post(s.server.get_io_service(), [&s] { s.flush(); });
}

bool WsServerCore::wait_for_full_subscriber(int timeout_ms, const std::atomic<bool>* stop) {
  Impl& s = *impl_;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  std::unique_lock lock(s.mutex);
  for (;;) {
    for (const auto& [h, c] : s.clients) {
      std::set<uint32_t> have;
      for (const auto& [sub, channel] : c.subscriptions) have.insert(channel);
      if (have.size() == s.channels.size()) return true;
    }
    if ((stop && stop->load()) || std::chrono::steady_clock::now() >= deadline) return false;
    // Woken by a subscribe; the short period only notices *stop (a signal).
    s.subscribed.wait_for(lock, std::chrono::milliseconds(100));
  }
}

WsCounters WsServerCore::counters() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->counters;
}

void WsServerCore::shutdown(int drain_ms) {
  Impl& s = *impl_;
  if (!s.thread.joinable()) return;
  {
    std::unique_lock lock(s.mutex);
    s.draining = true;
  }
  asio::post(s.server.get_io_service(), [&s] { s.flush(); });
  {
    std::unique_lock lock(s.mutex);
    s.drained.wait_for(lock, std::chrono::milliseconds(drain_ms), [&s] { return s.closed; });
  }
  // Still behind after drain_ms (a client that does not read): close anyway.
  asio::post(s.server.get_io_service(), [&s] {
    std::unique_lock lock(s.mutex);
    s.finish(lock);
  });
  {
    std::unique_lock lock(s.mutex);
    s.drained.wait_for(lock, std::chrono::milliseconds(1000), [&s] { return s.clients.empty(); });
  }
  s.retry->cancel();
  s.server.stop();
  s.thread.join();
}

}  // namespace tlvlink::foxglove::internal
