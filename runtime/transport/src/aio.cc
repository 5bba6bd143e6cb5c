#include "aio.h"

#include <sys/eventfd.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

namespace tlvlink::transport::internal {

Aio::~Aio() {
  if (context_ != 0) syscall(SYS_io_destroy, context_);
  if (event_fd_ >= 0) ::close(event_fd_);
}

Status Aio::setup(unsigned max_in_flight) {
  if (context_ != 0) return Status();
  event_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  TLV_ENSURE(event_fd_ >= 0, ErrorCode::kTransport, "eventfd: %s", std::strerror(errno));
  TLV_ENSURE(syscall(SYS_io_setup, max_in_flight, &context_) == 0, ErrorCode::kTransport,
             "io_setup: %s", std::strerror(errno));
  return Status();
}

Status Aio::submit(iocb& cb, int fd, bool write, void* buffer, size_t size, uint64_t tag) {
  std::memset(&cb, 0, sizeof(cb));
  cb.aio_data = tag;
  cb.aio_lio_opcode = write ? IOCB_CMD_PWRITE : IOCB_CMD_PREAD;
  cb.aio_fildes = static_cast<uint32_t>(fd);
  cb.aio_buf = reinterpret_cast<uint64_t>(buffer);
  cb.aio_nbytes = size;
  cb.aio_flags = IOCB_FLAG_RESFD;
  cb.aio_resfd = static_cast<uint32_t>(event_fd_);
  iocb* list[1] = {&cb};
  const long n = syscall(SYS_io_submit, context_, 1, list);
  if (n == 1) return Status();
  const int err = n < 0 ? errno : EAGAIN;
  return Error::make(err == EAGAIN || err == ESHUTDOWN || err == ENODEV
                         ? ErrorCode::kTransportDisconnected
                         : ErrorCode::kTransport,
                     "io_submit (%s): %s", write ? "write" : "read", std::strerror(err));
}

size_t Aio::reap(io_event* events, size_t max) { return reap_wait(events, max, 0); }

size_t Aio::reap_wait(io_event* events, size_t max, int timeout_ms) {
  uint64_t count;
  (void)!::read(event_fd_, &count,
                sizeof(count));  // reset the eventfd; completions are counted below
  timespec timeout{timeout_ms / 1000, static_cast<long>(timeout_ms % 1000) * 1'000'000};
  const long n = syscall(SYS_io_getevents, context_, timeout_ms > 0 ? 1 : 0, static_cast<long>(max),
                         events, &timeout);
  return n > 0 ? static_cast<size_t>(n) : 0;
}

void Aio::cancel(iocb& cb) {
  io_event ignored;
  syscall(SYS_io_cancel, context_, &cb, &ignored);
}

}  // namespace tlvlink::transport::internal
