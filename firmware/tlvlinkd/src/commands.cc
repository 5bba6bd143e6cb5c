#include "commands.h"

#include <charconv>

namespace tlvlink::daemon::internal {

bool parse_command(std::string_view line, int64_t now_ns, Command& out) {
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r' || line.back() == ' '))
    line.remove_suffix(1);
  out = Command{};
  out.t_ns = now_ns;
  if (line == "closed") {
    out.kind = CommandKind::kClosed;
    return true;
  }
  if (line == "lifting") {
    out.kind = CommandKind::kLifting;
    return true;
  }
  if (line.rfind("rezero", 0) != 0) return false;
  out.kind = CommandKind::kRezero;
  std::string_view rest = line.substr(6);
  if (rest.empty()) return true;
  if (rest.front() != ' ') return false;
  rest.remove_prefix(1);
  int32_t sensor = -1;
  const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), sensor);
  if (ec != std::errc() || end != rest.data() + rest.size() || sensor < 0) return false;
  out.sensor = sensor;
  return true;
}

bool CommandQueue::push(const Command& c) {
  std::lock_guard lock(mutex_);
  if (count_ == kCapacity) {
    ++dropped_;
    return false;
  }
  ring_[(head_ + count_) % kCapacity] = c;
  ++count_;
  return true;
}

bool CommandQueue::pop(Command& out) {
  std::lock_guard lock(mutex_);
  if (count_ == 0) return false;
  out = ring_[head_];
  head_ = (head_ + 1) % kCapacity;
  --count_;
  return true;
}

uint64_t CommandQueue::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

}  // namespace tlvlink::daemon::internal
