// USB bulk on the board through FunctionFS (ffs.h).
#include <fcntl.h>
#include <linux/usb/ch9.h>
#include <linux/usb/functionfs.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>

#include "aio.h"
#include "fd_util.h"
#include "tlvlink/transport/ffs.h"
#include "tlvlink/transport/usb_stream.h"
#include "usb_factory.h"

namespace tlvlink::transport {
namespace {

using internal::close_fd;

constexpr uint64_t kReadTag = 1, kWriteTag = 2;

class FfsTransport final : public Transport {
 public:
  explicit FfsTransport(FfsConfig config)
      : config_(std::move(config)),
        name_("usb-ffs:" + config_.dir),
        wake_(internal::make_wake_fd()) {}
  ~FfsTransport() override {
    close();
    close_fd(ep_in_);
    close_fd(ep_out_);
    close_fd(ep0_);  // the function disappears with it (the gadget is unbound)
    close_fd(wake_);
  }

  std::string_view name() const override { return name_; }
  bool is_open() const override { return open_; }
  bool peer_present() const override { return enabled_; }
  void interrupt() override { internal::signal_wake_fd(wake_); }

  Status open() override {
    if (ep0_ < 0) TLV_TRY(start_function());
    TLV_TRY(handle_events());
    if (!enabled_) {
      return Error::make(ErrorCode::kTransportUnavailable,
                         "%s: the USB host has not enabled the function yet", name_.c_str());
    }
    rx_len_ = rx_pos_ = 0;
    TLV_TRY(submit_read());
    open_ = true;
    return Status();
  }

  void close() override {
    if (!open_) return;
    open_ = false;
    if (rx_pending_) aio_.cancel(rx_cb_);
    if (tx_pending_) aio_.cancel(tx_cb_);
    // Cancelled operations still complete: reap them before their buffers can be reused.
    io_event events[4];
    for (int tries = 0; (rx_pending_ || tx_pending_) && tries < 20; ++tries) {
      const size_t n = aio_.reap_wait(events, 4, 50);
      for (size_t i = 0; i < n; ++i)
        (events[i].data == kReadTag ? rx_pending_ : tx_pending_) = false;
    }
    rx_pending_ = tx_pending_ = false;
  }

  // A bulk IN transfer completes when the host reads it; close() cancels one still pending, and
  // its bytes (the stream's last frame at a stop) never reach the host. So the Sender's flush
  // waits here, bounded, for the host to take it.
  void drain(int timeout_ms) override {
    for (int waited = 0; open_ && tx_pending_ && waited < timeout_ms; waited += 10) {
      pollfd fd{aio_.event_fd(), POLLIN, 0};
      if (::poll(&fd, 1, std::min(10, timeout_ms - waited)) < 0 && errno != EINTR) return;
      if (!reap().ok()) return;  // the link failed: nothing more will be read
    }
  }

  Result<Readiness> wait(bool want_write, int timeout_ms) override {
    TLV_ENSURE(open_, ErrorCode::kInvalidState, "%s: wait() on a closed link", name_.c_str());
    TLV_TRY(reap());
    Readiness ready{rx_pos_ < rx_len_, !tx_pending_};
    if (ready.readable || (want_write && ready.writable)) return ready;
    pollfd fds[3] = {{ep0_, POLLIN, 0}, {aio_.event_fd(), POLLIN, 0}, {wake_, POLLIN, 0}};
    if (::poll(fds, 3, timeout_ms) < 0 && errno != EINTR)
      return internal::io_error("poll", name_, errno);
    if (fds[2].revents & POLLIN) internal::drain_wake_fd(wake_);
    if (fds[0].revents & POLLIN) TLV_TRY(handle_events());
    if (!enabled_)
      return Error::make(ErrorCode::kTransportDisconnected,
                         "%s: the USB host disabled the function", name_.c_str());
    TLV_TRY(reap());
    return Readiness{rx_pos_ < rx_len_, !tx_pending_};
  }

  Result<size_t> read(std::span<std::byte> out) override {
    TLV_TRY(reap());
    const size_t n = std::min(out.size(), rx_len_ - rx_pos_);
    std::memcpy(out.data(), rx_ + rx_pos_, n);
    rx_pos_ += n;
    if (rx_pos_ == rx_len_ && !rx_pending_) TLV_TRY(submit_read());
    return n;
  }

  Result<size_t> write(std::span<const std::byte> data) override {
    TLV_TRY(reap());
    if (tx_pending_ || data.empty()) return size_t{0};
    const size_t n = usb_chunk(data.size());
    std::memcpy(tx_, data.data(), n);
    size_t len = n;
    if (usb_needs_pad(len)) tx_[len++] = std::byte{0};
    TLV_TRY(aio_.submit(tx_cb_, ep_in_, true, tx_, len, kWriteTag));
    tx_pending_ = true;
    return n;
  }

 private:
  // ep0: descriptors, strings; then the endpoint files exist. Optionally bind the gadget.
  Status start_function() {
    const std::string ep0 = config_.dir + "/ep0";
    ep0_ = ::open(ep0.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (ep0_ < 0) {
      return internal::open_error("opening (is functionfs mounted? see scripts/usb_gadget.sh)", ep0,
                                  errno);
    }
    std::byte blob[256];
    const size_t nd = ffs_descriptors(blob);
    if (::write(ep0_, blob, nd) != static_cast<ssize_t>(nd))
      return fail_function("writing descriptors to", ep0);
    const size_t ns = ffs_strings(blob);
    if (::write(ep0_, blob, ns) != static_cast<ssize_t>(ns))
      return fail_function("writing strings to", ep0);
    ep_in_ = ::open((config_.dir + "/ep1").c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
    ep_out_ = ::open((config_.dir + "/ep2").c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (ep_in_ < 0 || ep_out_ < 0) return fail_function("opening the endpoints of", config_.dir);
    TLV_TRY(aio_.setup(4));
    if (!config_.udc.empty() && !config_.gadget.empty()) TLV_TRY(bind());
    return Status();
  }

  Status fail_function(const char* what, const std::string& where) {
    const int err = errno;
    close_fd(ep_in_);
    close_fd(ep_out_);
    close_fd(ep0_);
    return Error::make(ErrorCode::kTransport, "%s %s: %s", what, where.c_str(), std::strerror(err));
  }

  Status bind() {
    const std::string path = config_.gadget + "/UDC";
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) return internal::open_error("binding the gadget: opening", path, errno);
    const ssize_t n = ::write(fd, config_.udc.data(), config_.udc.size());
    const int err = errno;
    ::close(fd);
    // EBUSY: already bound (by usb_gadget.sh or an earlier run).
    TLV_ENSURE(n == static_cast<ssize_t>(config_.udc.size()) || err == EBUSY, ErrorCode::kTransport,
               "binding the gadget to %s (%s): %s", config_.udc.c_str(), path.c_str(),
               std::strerror(err));
    return Status();
  }

  // ep0 events: ENABLE/DISABLE track whether the host uses the function; control requests
  // (none are defined for the stream) are stalled.
  Status handle_events() {
    usb_functionfs_event events[8];
    for (;;) {
      const ssize_t n = ::read(ep0_, events, sizeof(events));
      if (n < 0) {
        if (errno == EAGAIN || errno == EINTR) return Status();
        return internal::io_error("reading events from", name_, errno);
      }
      for (size_t i = 0; i < static_cast<size_t>(n) / sizeof(events[0]); ++i) {
        switch (events[i].type) {
          case FUNCTIONFS_ENABLE: enabled_ = true; break;
          case FUNCTIONFS_DISABLE:
          case FUNCTIONFS_UNBIND:
          case FUNCTIONFS_SUSPEND: enabled_ = false; break;
          case FUNCTIONFS_SETUP:
            // Stall: answer in the direction opposite to the request's data stage.
            if (events[i].u.setup.bRequestType & USB_DIR_IN)
              (void)!::read(ep0_, nullptr, 0);
            else
              (void)!::write(ep0_, nullptr, 0);
            break;
          default: break;  // BIND, RESUME
        }
      }
      if (static_cast<size_t>(n) < sizeof(events)) return Status();
    }
  }

  Status submit_read() {
    rx_len_ = rx_pos_ = 0;
    TLV_TRY(aio_.submit(rx_cb_, ep_out_, false, rx_, sizeof(rx_), kReadTag));
    rx_pending_ = true;
    return Status();
  }

  Status reap() {
    io_event events[4];
    const size_t n = aio_.reap(events, 4);
    for (size_t i = 0; i < n; ++i) {
      const long long res = static_cast<long long>(events[i].res);
      if (events[i].data == kReadTag) {
        rx_pending_ = false;
        if (res < 0) return internal::io_error("bulk OUT read", name_, static_cast<int>(-res));
        rx_len_ = static_cast<size_t>(res), rx_pos_ = 0;
        if (rx_len_ == 0 && open_) TLV_TRY(submit_read());  // zero-length packet
      } else {
        tx_pending_ = false;
        if (res < 0) return internal::io_error("bulk IN write", name_, static_cast<int>(-res));
      }
    }
    return Status();
  }

  FfsConfig config_;
  std::string name_;
  int ep0_ = -1, ep_in_ = -1, ep_out_ = -1, wake_ = -1;
  bool open_ = false, enabled_ = false;
  internal::Aio aio_;
  iocb rx_cb_{}, tx_cb_{};
  bool rx_pending_ = false, tx_pending_ = false;
  alignas(64) std::byte rx_[kUsbMaxTransfer];
  alignas(64) std::byte tx_[kUsbMaxTransfer];
  size_t rx_len_ = 0, rx_pos_ = 0;
};

}  // namespace

Result<std::unique_ptr<Transport>> make_ffs_transport(const FfsConfig& config) {
  TLV_ENSURE(!config.dir.empty(), ErrorCode::kInvalidArgument, "usb link: no FunctionFS directory");
  TLV_ENSURE(config.udc.empty() == config.gadget.empty(), ErrorCode::kInvalidArgument,
             "usb link: udc and gadget go together (the transport binds gadget/UDC to udc)");
  return std::unique_ptr<Transport>(std::make_unique<FfsTransport>(config));
}

namespace internal {
Result<std::unique_ptr<Transport>> make_usb_device_transport(const std::string& ffs_dir,
                                                             const std::string& udc,
                                                             const std::string& gadget) {
  return make_ffs_transport(FfsConfig{ffs_dir, udc, gadget});
}
}  // namespace internal

}  // namespace tlvlink::transport
