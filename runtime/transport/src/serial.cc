// Serial links through termios (UART, CDC-ACM, pty slave).
#include "tlvlink/transport/serial.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "fd_util.h"

namespace tlvlink::transport {
namespace {

using internal::close_fd;

bool baud_constant(int baud, speed_t& out) {
  struct Rate {
    int baud;
    speed_t constant;
  };
  static constexpr Rate kRates[] = {{1200, B1200},       {2400, B2400},       {4800, B4800},
                                    {9600, B9600},       {19200, B19200},     {38400, B38400},
                                    {57600, B57600},     {115200, B115200},   {230400, B230400},
                                    {460800, B460800},   {500000, B500000},   {576000, B576000},
                                    {921600, B921600},   {1000000, B1000000}, {1152000, B1152000},
                                    {1500000, B1500000}, {2000000, B2000000}, {2500000, B2500000},
                                    {3000000, B3000000}, {3500000, B3500000}, {4000000, B4000000}};
  for (const Rate& r : kRates) {
    if (r.baud == baud) {
      out = r.constant;
      return true;
    }
  }
  return false;
}

class SerialTransport final : public Transport {
 public:
  explicit SerialTransport(SerialConfig config)
      : config_(std::move(config)),
        name_("serial:" + config_.path),
        wake_(internal::make_wake_fd()) {}
  ~SerialTransport() override {
    close();
    close_fd(wake_);
  }

  std::string_view name() const override { return name_; }
  bool is_open() const override { return fd_ >= 0; }

  Status open() override {
    close();
    const int fd = ::open(config_.path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return internal::open_error("opening", config_.path, errno);
    termios tio;
    if (tcgetattr(fd, &tio) != 0) {
      const int err = errno;
      ::close(fd);
      return Error::make(ErrorCode::kTransport, "%s is not a terminal (tcgetattr: %s)",
                         config_.path.c_str(), std::strerror(err));
    }
    const bool was_cooked = (tio.c_lflag & (ICANON | ECHO)) != 0;
    cfmakeraw(&tio);  // 8 data bits, no parity, no echo, no line editing, no CR/LF mapping
    tio.c_cflag |= CLOCAL | CREAD;
    tio.c_cflag &= ~CSTOPB;
    if (config_.flow == FlowControl::kRtsCts)
      tio.c_cflag |= CRTSCTS;
    else
      tio.c_cflag &= ~CRTSCTS;
    // VMIN 1: with O_NONBLOCK an empty line reads as EAGAIN and 0 means end of file (hangup).
    // With VMIN 0 an empty tty reads as 0 on some kernels (the emulated board's 6.1 on
    // /dev/ttyGS0), which looked like end of file after every burst of commands: the board
    // reconnected and lost its replies.
    tio.c_cc[VMIN] = 1;
    tio.c_cc[VTIME] = 0;
    speed_t speed;
    if (config_.baud != 0 && baud_constant(config_.baud, speed)) {
      cfsetispeed(&tio, speed);
      cfsetospeed(&tio, speed);
    }
    if (tcsetattr(fd, TCSANOW, &tio) != 0) {
      const int err = errno;
      ::close(fd);
      return Error::make(ErrorCode::kTransport, "configuring %s (raw, %d baud): %s",
                         config_.path.c_str(), config_.baud, std::strerror(err));
    }
    // A tty that was cooked until now (a CDC-ACM tty after enumeration: echo, CR/LF mapping,
    // XON/XOFF, line buffering) may have mangled what arrived since open(): drop it rather than
    // hand on mangled bytes; the stream resynchronises at the next delimiter (the host asks for a
    // Hello). A tty already raw (a pty set up by PtyTransport, a reopen) keeps its input.
    if (was_cooked) (void)tcflush(fd, TCIFLUSH);
    fd_ = fd;
    return Status();
  }

  void close() override { close_fd(fd_); }

  Result<Readiness> wait(bool want_write, int timeout_ms) override {
    TLV_ENSURE(fd_ >= 0, ErrorCode::kInvalidState, "%s: wait() on a closed link", name_.c_str());
    const short events = static_cast<short>(POLLIN | (want_write ? POLLOUT : 0));
    TLV_ASSIGN_OR_RETURN(const short revents,
                         internal::poll_with_wake(fd_, events, wake_, timeout_ms));
    // Hangup: the pty master closed, the USB device or gadget went away.
    if (revents & (POLLHUP | POLLERR | POLLNVAL)) {
      return Error::make(ErrorCode::kTransportDisconnected, "%s: hangup", name_.c_str());
    }
    return Readiness{(revents & POLLIN) != 0, (revents & POLLOUT) != 0};
  }

  Result<size_t> read(std::span<std::byte> out) override {
    const ssize_t n = ::read(fd_, out.data(), out.size());
    if (n > 0) return static_cast<size_t>(n);
    if (n == 0)
      return Error::make(ErrorCode::kTransportDisconnected, "%s: end of file", name_.c_str());
    if (errno == EAGAIN || errno == EINTR) return size_t{0};
    return internal::io_error("read", name_, errno);
  }

  Result<size_t> write(std::span<const std::byte> data) override {
    const ssize_t n = ::write(fd_, data.data(), data.size());
    if (n >= 0) return static_cast<size_t>(n);
    if (errno == EAGAIN || errno == EINTR) return size_t{0};
    return internal::io_error("write", name_, errno);
  }

  void interrupt() override { internal::signal_wake_fd(wake_); }

  void drain(int timeout_ms) override {
    for (int waited = 0; fd_ >= 0 && waited < timeout_ms; waited += 5) {
      int queued = 0;
      if (::ioctl(fd_, TIOCOUTQ, &queued) != 0 || queued == 0) return;
      ::usleep(5000);
    }
  }

 private:
  SerialConfig config_;
  std::string name_;
  int fd_ = -1, wake_ = -1;
};

}  // namespace

Result<std::unique_ptr<Transport>> make_serial_transport(const SerialConfig& config) {
  TLV_ENSURE(!config.path.empty(), ErrorCode::kInvalidArgument, "serial link: no device path");
  speed_t speed;
  TLV_ENSURE(config.baud == 0 || baud_constant(config.baud, speed), ErrorCode::kInvalidArgument,
             "serial link %s: %d baud is not a standard rate (1200 ... 4000000)",
             config.path.c_str(), config.baud);
  auto t = std::make_unique<SerialTransport>(config);
  return std::unique_ptr<Transport>(std::move(t));
}

}  // namespace tlvlink::transport
