#include "corrupting_transport.h"

#include <algorithm>
#include <cstdio>

namespace tlvlink::testing {

CorruptingTransport::CorruptingTransport(std::unique_ptr<transport::Transport> inner,
                                         ByteFaultRates rates)
    : inner_(std::move(inner)), faults_(rates) {
  char text[96];
  std::snprintf(text, sizeof(text), " (damaged: byte errors %g, drops %g, seed %llu)",
                rates.byte_error_rate, rates.byte_drop_rate,
                static_cast<unsigned long long>(rates.seed));
  name_ = std::string(inner_->name()) + text;
}

Status CorruptingTransport::open() {
  staged_len_ = staged_pos_ = 0;
  return inner_->open();
}

void CorruptingTransport::close() {
  staged_len_ = staged_pos_ = 0;
  inner_->close();
}

Status CorruptingTransport::flush() {
  while (staged_pos_ < staged_len_) {
    TLV_ASSIGN_OR_RETURN(
        size_t n, inner_->write(std::span(staged_ + staged_pos_, staged_len_ - staged_pos_)));
    if (n == 0) break;
    staged_pos_ += n;
  }
  if (staged_pos_ == staged_len_) staged_len_ = staged_pos_ = 0;
  return Status();
}

Result<transport::Readiness> CorruptingTransport::wait(bool want_write, int timeout_ms) {
  TLV_TRY(flush());
  const bool staged = staged_len_ > 0;
  TLV_ASSIGN_OR_RETURN(transport::Readiness r, inner_->wait(want_write || staged, timeout_ms));
  if (staged && r.writable) {
    TLV_TRY(flush());
  }
  // Writable to the caller only when nothing of the last write is still staged.
  r.writable = r.writable && staged_len_ == 0;
  return r;
}

Result<size_t> CorruptingTransport::write(std::span<const std::byte> data) {
  TLV_TRY(flush());
  if (staged_len_ > 0 || data.empty()) return size_t{0};
  const size_t take = std::min(data.size(), sizeof(staged_));
  {
    std::lock_guard lock(mutex_);
    staged_len_ = faults_.apply(data.first(take), staged_);
  }
  staged_pos_ = 0;
  TLV_TRY(flush());
  return take;
}

void CorruptingTransport::drain(int timeout_ms) {
  for (int waited = 0; staged_len_ > 0 && waited < timeout_ms; waited += 10) {
    if (!flush().ok()) break;
    if (staged_len_ > 0) (void)inner_->wait(true, 10);
  }
  inner_->drain(timeout_ms);
}

ByteFaultCounts CorruptingTransport::counts() const {
  std::lock_guard lock(mutex_);
  return faults_.counts();
}

}  // namespace tlvlink::testing
