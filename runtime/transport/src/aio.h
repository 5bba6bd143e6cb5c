#pragma once
// Linux native AIO through raw syscalls (no libaio), completing into an eventfd that poll() can
// watch: FunctionFS endpoint files support AIO but not poll(). Internal to tlvlink_transport.
#ifndef TLVLINK_TRANSPORT_PRIVATE
#error "aio.h is internal to tlvlink_transport"
#endif

#include <linux/aio_abi.h>

#include <cstddef>

#include "tlvlink/error.h"

namespace tlvlink::transport::internal {

class Aio {
 public:
  Aio() = default;
  ~Aio();
  Aio(const Aio&) = delete;
  Aio& operator=(const Aio&) = delete;

  Status setup(unsigned max_in_flight);
  int event_fd() const { return event_fd_; }
  // Prepares and submits one read or write of `fd` into/from `buffer`; completion signals the
  // eventfd. `cb` and `buffer` must stay valid until the completion is reaped.
  Status submit(iocb& cb, int fd, bool write, void* buffer, size_t size, uint64_t tag);
  // Completed operations, without waiting (0 if none).
  size_t reap(io_event* events, size_t max);
  // Asks the kernel to cancel `cb` (FunctionFS supports it); its completion still arrives.
  void cancel(iocb& cb);
  // Waits up to timeout_ms for completions (after cancel()).
  size_t reap_wait(io_event* events, size_t max, int timeout_ms);

 private:
  aio_context_t context_ = 0;
  int event_fd_ = -1;
};

}  // namespace tlvlink::transport::internal
