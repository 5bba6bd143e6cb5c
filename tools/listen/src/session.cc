#include "tlvlink/listen/session.h"

#include <poll.h>
#include <unistd.h>

#include <map>
#include <mutex>
#include <thread>

#include "tlvlink/listen/command_text.h"
#include "tlvlink/listen/format.h"
#include "tlvlink/protocol/names.h"
#include "tlvlink/transport/time.h"

namespace tlvlink::listen {
namespace {

using transport::monotonic_ns;

// Commands typed on stdin, read by a helper thread (poll with a timeout so it ends with the
// session).
class StdinCommands {
 public:
  StdinCommands(Client& client, std::FILE* log, const std::atomic<bool>& stop)
      : client_(client), log_(log), stop_(stop) {
    thread_ = std::thread([this] { loop(); });
  }
  ~StdinCommands() {
    done_ = true;
    thread_.join();
  }

 private:
  void loop() {
    std::string line;
    char buf[256];
    while (!done_ && !stop_) {
      pollfd p{0, POLLIN, 0};
      if (::poll(&p, 1, 100) <= 0) continue;
      const ssize_t n = ::read(0, buf, sizeof(buf));
      if (n <= 0) return;
      line.append(buf, static_cast<size_t>(n));
      for (size_t nl; (nl = line.find('\n')) != std::string::npos; line.erase(0, nl + 1)) {
        const std::string text = line.substr(0, nl);
        if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
        Result<protocol::Command> c = parse_command(text);
        Result<uint32_t> seq = c.ok() ? client_.send(c.value()) : Result<uint32_t>(c.error());
        if (!seq.ok())
          std::fprintf(log_, "# command '%s': %s\n", text.c_str(), seq.error().message());
        else
          std::fprintf(log_, "# sent #%u %s\n", seq.value(), text.c_str());
      }
    }
  }
  Client& client_;
  std::FILE* log_;
  const std::atomic<bool>& stop_;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

}  // namespace

Result<int> run_session(const SessionOptions& o, std::FILE* out, std::FILE* log,
                        const std::atomic<bool>& stop) {
  // Commands are checked before anything is opened: a typo is a usage error.
  std::vector<protocol::Command> commands;
  for (const std::string& text : o.commands) {
    TLV_ASSIGN_OR_RETURN(protocol::Command c, parse_command(text));
    commands.push_back(c);
  }
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Client> client,
                       o.open_client ? o.open_client(o.client) : Client::open(o.source, o.client));
  std::unique_ptr<StdinCommands> typed;
  if (o.stdin_commands) typed = std::make_unique<StdinCommands>(*client, log, stop);

  std::map<uint32_t, std::string> awaiting;  // command sequence -> its text
  bool sent = commands.empty(), refused = false;
  uint64_t predictions = 0;
  const int64_t start = monotonic_ns();
  int64_t next_stats =
      o.stats_every_ms > 0 ? start + int64_t{o.stats_every_ms} * 1'000'000 : INT64_MAX;
  int64_t replies_deadline = INT64_MAX;
  std::optional<Message> hello;

  auto print_stats = [&] {
    const LinkStats s = client->stats();
    if (o.json)
      std::fprintf(out, "{\"type\":\"link_stats\",\"stats\":%s}\n", stats_json(s).c_str());
    std::fprintf(log, "%s", stats_text(s).c_str());
    std::fflush(out);
  };

  for (;;) {
    if (stop) break;
    const int64_t now = monotonic_ns();
    if (o.duration_ms >= 0 && now - start >= o.duration_ms * 1'000'000) break;
    if (now >= next_stats) {
      print_stats();
      next_stats = now + int64_t{o.stats_every_ms} * 1'000'000;
    }
    if (!sent && now >= replies_deadline) break;
    Result<std::optional<Message>> r = client->next(100);
    for (const LinkEvent& e : client->take_events()) {
      std::fprintf(log, "# %s: %s\n", link_event_name(e.kind), e.text.c_str());
    }
    if (!r.ok()) {
      std::fprintf(log, "tlvlink listen: error [%s]: %s\n", error_code_name(r.error().code()),
                   r.error().message());
      print_stats();
      return 1;
    }
    if (!r.value()) {
      if (client->ended()) break;
      continue;
    }
    const Message& m = *r.value();
    if (m.type() == protocol::MessageType::kHello) hello = m;
    const FormatContext context{hello ? &*hello : nullptr};
    std::fprintf(out, "%s\n", (o.json ? json_line(m, context) : text_line(m, context)).c_str());
    std::fflush(out);
    for (MessageSink* sink : o.sinks) {
      if (Status st = sink->on_message(m, context); !st.ok()) {
        std::fprintf(log, "tlvlink listen: error [%s]: %s\n", error_code_name(st.error().code()),
                     st.error().message());
        print_stats();
        return 1;
      }
    }
    // Replies to our commands.
    uint32_t answered = 0;
    bool have_answer = false, ok = true;
    if (auto a = m.ack(); a.ok()) answered = a.value().command_sequence, have_answer = true;
    if (auto n = m.nack(); n.ok())
      answered = n.value().command_sequence, have_answer = true, ok = false;
    if (auto p = m.pong(); p.ok()) answered = p.value().command_sequence, have_answer = true;
    if (have_answer && awaiting.erase(answered) > 0 && !ok) refused = true;
    if (m.type() == protocol::MessageType::kFramePrediction && o.max_predictions > 0 &&
        ++predictions >= o.max_predictions)
      break;
    // Commands go once the board has greeted us (it is there and listening).
    if (!sent && hello) {
      for (size_t i = 0; i < commands.size(); ++i) {
        Result<uint32_t> seq = client->send(commands[i]);
        if (!seq.ok()) {
          std::fprintf(log, "# command '%s': %s\n", o.commands[i].c_str(), seq.error().message());
          refused = true;
          continue;
        }
        awaiting[seq.value()] = o.commands[i];
        std::fprintf(log, "# sent #%u %s\n", seq.value(), o.commands[i].c_str());
      }
      sent = true;
      replies_deadline = monotonic_ns() + int64_t{o.reply_timeout_ms} * 1'000'000;
    }
    if (o.exit_after_replies && sent && awaiting.empty()) break;
    if (o.exit_after_replies && sent && monotonic_ns() >= replies_deadline) break;
  }
  for (const auto& [seq, text] : awaiting)
    std::fprintf(log, "# no answer to #%u %s\n", seq, text.c_str());
  if (o.exit_after_replies && !sent)
    std::fprintf(log, "# the board never said hello: commands not sent\n");
  print_stats();
  const bool failed = refused || (o.exit_after_replies && (!sent || !awaiting.empty()));
  return failed ? 1 : 0;
}

}  // namespace tlvlink::listen
