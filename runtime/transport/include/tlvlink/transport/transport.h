#pragma once
// One interface for every link the stream runs over: a UART, USB CDC-ACM (/dev/ttyGS0 on the
// board, /dev/ttyACM0 on the host), a pty in tests, USB bulk through FunctionFS on the board or
// libusb on the host. Poll-style: wait() for readiness, then non-blocking read()/write(), so
// one thread can serve both directions and be woken at once when there is something to send.
//
// Threading: wait/read/write/open/close from one thread (the link's I/O thread); interrupt()
// from any thread.

#include <cstddef>
#include <span>
#include <string_view>

#include "tlvlink/error.h"

namespace tlvlink::transport {

struct Readiness {
  bool readable = false;
  bool writable = false;
};

class Transport {
 public:
  virtual ~Transport() = default;

  // What the link is, for messages: "serial:/dev/ttyGS0", "pty:/dev/pts/3 (link /tmp/x)".
  virtual std::string_view name() const = 0;

  // Opens the link. kTransportUnavailable while the device or path is absent: retry later.
  virtual Status open() = 0;
  virtual void close() = 0;
  virtual bool is_open() const = 0;

  // Waits until the link can be read (always asked) or written (when want_write), interrupt()
  // is called, or timeout_ms passes (Readiness all false). kTransportDisconnected when the link
  // went away (hangup, unplug, unbind): close() it and open() it again.
  virtual Result<Readiness> wait(bool want_write, int timeout_ms) = 0;

  // Non-blocking. read: bytes read, 0 if none now. write: bytes accepted (maybe fewer than
  // given), 0 if there is no room now. kTransportDisconnected as for wait().
  virtual Result<size_t> read(std::span<std::byte> out) = 0;
  virtual Result<size_t> write(std::span<const std::byte> data) = 0;

  // Makes the current (or next) wait() return early. Thread-safe, never blocks.
  virtual void interrupt() = 0;

  // Waits up to timeout_ms until what was written has left this end (a UART's output queue is
  // empty, a pty's reader has read it), so close() does not discard it. Default: no wait.
  virtual void drain(int timeout_ms) { (void)timeout_ms; }

  // Whether someone is there to read what is written. A pty with no reader or a USB function
  // the host has not enabled: false, and the sender keeps what it would send. Links that cannot
  // tell (a UART) say true; the sender then judges by whether bytes move.
  virtual bool peer_present() const { return true; }
};

}  // namespace tlvlink::transport
