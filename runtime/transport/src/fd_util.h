#pragma once
// File-descriptor helpers shared by the fd-based transports (serial, pty, FunctionFS): the
// eventfd behind interrupt(), poll() with it, and errno -> tlvlink::Error at the boundary.
#ifndef TLVLINK_TRANSPORT_PRIVATE
#error "fd_util.h is internal to tlvlink_transport: include tlvlink/transport/*.h instead"
#endif

#include <cstddef>
#include <string_view>

#include "tlvlink/error.h"

namespace tlvlink::transport::internal {

// An eventfd (non-blocking, close-on-exec) for interrupt(); -1 if the kernel refused one.
int make_wake_fd();
void signal_wake_fd(int fd);
void drain_wake_fd(int fd);
void close_fd(int& fd);  // closes if >= 0 and sets -1

// errno after a failed open(): absent-device errors are kTransportUnavailable, the rest kTransport.
Error open_error(std::string_view what, std::string_view path, int err);
// errno after a failed read/write/poll: hangup-like errors are kTransportDisconnected.
Error io_error(std::string_view what, std::string_view name, int err);
bool is_disconnect_errno(int err);

// poll() on `fd` (events) and the wake fd for up to timeout_ms; returns the fd's revents (0 on
// timeout or wake-up). EINTR counts as a wake-up.
Result<short> poll_with_wake(int fd, short events, int wake_fd, int timeout_ms);

}  // namespace tlvlink::transport::internal
