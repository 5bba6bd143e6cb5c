// USB bulk on the host through libusb (usb_host.h): asynchronous transfers, events handled in
// wait() with a timeout, interrupt() through libusb_interrupt_event_handler.
#include <libusb.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include "tlvlink/listen/usb_host.h"

namespace tlvlink::listen {
namespace {

using transport::kUsbMaxTransfer;

Error usb_error(ErrorCode code, const char* what, int rc) {
  return Error::make(code, "libusb %s: %s", what, libusb_strerror(static_cast<libusb_error>(rc)));
}

struct StreamInterface {
  int number = -1;
  uint8_t in = 0, out = 0;
};

// The stream interface of a device's active configuration, if it has one.
StreamInterface find_stream_interface(libusb_device* dev) {
  StreamInterface found;
  libusb_config_descriptor* config = nullptr;
  if (libusb_get_active_config_descriptor(dev, &config) != 0) return found;
  for (int i = 0; i < config->bNumInterfaces && found.number < 0; ++i) {
    for (int a = 0; a < config->interface[i].num_altsetting; ++a) {
      const libusb_interface_descriptor& d = config->interface[i].altsetting[a];
      if (d.bInterfaceClass != transport::kUsbInterfaceClass ||
          d.bInterfaceSubClass != transport::kUsbInterfaceSubclass ||
          d.bInterfaceProtocol != transport::kUsbInterfaceProtocol) {
        continue;
      }
      StreamInterface s{d.bInterfaceNumber, 0, 0};
      for (int e = 0; e < d.bNumEndpoints; ++e) {
        const libusb_endpoint_descriptor& ep = d.endpoint[e];
        if ((ep.bmAttributes & 0x3) != LIBUSB_TRANSFER_TYPE_BULK) continue;
        if (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN)
          s.in = ep.bEndpointAddress;
        else
          s.out = ep.bEndpointAddress;
      }
      if (s.in != 0 && s.out != 0) found = s;
    }
  }
  libusb_free_config_descriptor(config);
  return found;
}

class UsbHostTransport final : public transport::Transport {
 public:
  explicit UsbHostTransport(UsbSelector selector) : selector_(std::move(selector)) {
    char name[80];
    std::snprintf(name, sizeof(name), "usb:%04x:%04x%s%s", selector_.vendor, selector_.product,
                  selector_.serial.empty() ? "" : ",serial=", selector_.serial.c_str());
    name_ = name;
  }
  ~UsbHostTransport() override {
    close();
    if (context_) libusb_exit(context_);
  }

  std::string_view name() const override { return name_; }
  bool is_open() const override { return handle_ != nullptr; }
  void interrupt() override {
    std::lock_guard lock(context_mutex_);
    if (context_) libusb_interrupt_event_handler(context_);
  }

  Status open() override {
    close();
    // A fresh context for every attempt: its device list is read from sysfs now. A context kept
    // from before learns of new devices only through hotplug events, which do not always arrive
    // (seen in the emulated board: the board's gadget bound after the client started was never
    // listed; containers often have no uevents at all).
    {
      std::lock_guard lock(context_mutex_);
      if (context_) libusb_exit(context_);
      context_ = nullptr;
      init_rc_ = libusb_init(&context_);
      if (init_rc_ != 0) context_ = nullptr;
    }
    if (init_rc_ != 0) return usb_error(ErrorCode::kTransportUnavailable, "init", init_rc_);
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(context_, &list);
    if (n < 0)
      return usb_error(ErrorCode::kTransportUnavailable, "listing devices", static_cast<int>(n));
    std::vector<UsbCandidate> found;
    std::vector<libusb_device*> devices;
    for (ssize_t i = 0; i < n; ++i) {
      libusb_device_descriptor d;
      if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
      if (d.idVendor != selector_.vendor || d.idProduct != selector_.product) continue;
      UsbCandidate c;
      c.vendor = d.idVendor, c.product = d.idProduct;
      c.bus = libusb_get_bus_number(list[i]), c.address = libusb_get_device_address(list[i]);
      c.has_stream_interface = find_stream_interface(list[i]).number >= 0;
      libusb_device_handle* h = nullptr;
      if (libusb_open(list[i], &h) == 0) {
        unsigned char serial[128] = {};
        if (d.iSerialNumber != 0 &&
            libusb_get_string_descriptor_ascii(h, d.iSerialNumber, serial, sizeof(serial)) > 0) {
          c.serial = reinterpret_cast<const char*>(serial);
        }
        libusb_close(h);
      } else {
        c.accessible = false;
      }
      found.push_back(c);
      devices.push_back(list[i]);
    }
    Result<size_t> chosen = select_usb_device(found, selector_);
    Status status;
    if (!chosen.ok()) {
      status = chosen.error();
    } else {
      status = claim(devices[chosen.value()]);
    }
    libusb_free_device_list(list, 1);
    return status;
  }

  void close() override {
    if (!handle_) return;
    for (libusb_transfer* t : {rx_transfer_, tx_transfer_}) {
      if ((t == rx_transfer_ ? rx_pending_ : tx_pending_)) libusb_cancel_transfer(t);
    }
    timeval tv{0, 100'000};
    for (int tries = 0; (rx_pending_ || tx_pending_) && tries < 20; ++tries) {
      libusb_handle_events_timeout_completed(context_, &tv, nullptr);
    }
    // A transfer holds a reference to the device it was last submitted on (libusb 1.0.26), so it
    // is freed here, while that device's context is alive; reusing it after open() renewed the
    // context made its next submit destroy a device of the freed context (a crash on replug).
    // One still in flight after the drain cannot be freed safely: it is abandoned (a few hundred
    // bytes; the kernel cancels its URB when the handle closes).
    if (!rx_pending_) libusb_free_transfer(rx_transfer_);
    if (!tx_pending_) libusb_free_transfer(tx_transfer_);
    rx_transfer_ = tx_transfer_ = nullptr;
    libusb_release_interface(handle_, interface_);
    libusb_close(handle_);
    handle_ = nullptr;
    rx_pending_ = tx_pending_ = false;
  }

  Result<transport::Readiness> wait(bool want_write, int timeout_ms) override {
    TLV_ENSURE(handle_ != nullptr, ErrorCode::kInvalidState, "%s: wait() on a closed link",
               name_.c_str());
    TLV_TRY(check());
    auto ready = [&] { return transport::Readiness{rx_pos_ < rx_len_, !tx_pending_}; };
    if (ready().readable || (want_write && ready().writable)) return ready();
    int completed = 0;
    completed_ = &completed;
    timeval tv{timeout_ms / 1000, static_cast<long>(timeout_ms % 1000) * 1000};
    const int rc = libusb_handle_events_timeout_completed(context_, &tv, &completed);
    completed_ = nullptr;
    if (rc != 0 && rc != LIBUSB_ERROR_INTERRUPTED)
      return usb_error(ErrorCode::kTransport, "handling events", rc);
    TLV_TRY(check());
    return ready();
  }

  Result<size_t> read(std::span<std::byte> out) override {
    TLV_TRY(check());
    const size_t n = std::min(out.size(), rx_len_ - rx_pos_);
    std::memcpy(out.data(), rx_ + rx_pos_, n);
    rx_pos_ += n;
    if (rx_pos_ == rx_len_ && !rx_pending_) TLV_TRY(submit_read());
    return n;
  }

  Result<size_t> write(std::span<const std::byte> data) override {
    TLV_TRY(check());
    if (tx_pending_ || data.empty()) return size_t{0};
    const size_t n = transport::usb_chunk(data.size());
    std::memcpy(tx_, data.data(), n);
    int len = static_cast<int>(n);
    if (transport::usb_needs_pad(n)) tx_[len++] = 0;
    libusb_fill_bulk_transfer(tx_transfer_, handle_, out_endpoint_, tx_, len,
                              &UsbHostTransport::on_tx, this, 0);
    const int rc = libusb_submit_transfer(tx_transfer_);
    if (rc != 0) return usb_error(ErrorCode::kTransportDisconnected, "bulk OUT", rc);
    tx_pending_ = true;
    return n;
  }

 private:
  Status claim(libusb_device* dev) {
    const StreamInterface s = find_stream_interface(dev);
    int rc = libusb_open(dev, &handle_);
    if (rc != 0) {
      handle_ = nullptr;
      return usb_error(ErrorCode::kTransportUnavailable, "opening the board", rc);
    }
    libusb_set_auto_detach_kernel_driver(handle_, 1);
    rc = libusb_claim_interface(handle_, s.number);
    if (rc != 0) {
      libusb_close(handle_);
      handle_ = nullptr;
      return usb_error(ErrorCode::kTransportUnavailable,
                       "claiming the stream interface (another reader?)", rc);
    }
    interface_ = s.number, in_endpoint_ = s.in, out_endpoint_ = s.out;
    failed_ = false;
    // Transfers belong to one connection (see close()).
    rx_transfer_ = libusb_alloc_transfer(0);
    tx_transfer_ = libusb_alloc_transfer(0);
    if (!rx_transfer_ || !tx_transfer_) {
      close();
      return Error::make(ErrorCode::kOutOfMemory, "%s: libusb could not allocate a transfer",
                         name_.c_str());
    }
    return submit_read();
  }

  Status submit_read() {
    rx_len_ = rx_pos_ = 0;
    libusb_fill_bulk_transfer(rx_transfer_, handle_, in_endpoint_, rx_,
                              static_cast<int>(kUsbMaxTransfer), &UsbHostTransport::on_rx, this, 0);
    const int rc = libusb_submit_transfer(rx_transfer_);
    if (rc != 0) return usb_error(ErrorCode::kTransportDisconnected, "bulk IN", rc);
    rx_pending_ = true;
    return Status();
  }

  Status check() {
    if (!failed_) return Status();
    return Error::make(ErrorCode::kTransportDisconnected, "%s: %s", name_.c_str(), failure_);
  }

  void fail(const char* what, libusb_transfer_status status) {
    failed_ = true;
    std::snprintf(failure_, sizeof(failure_), "%s %s", what, libusb_error_name(status));
  }

  static void LIBUSB_CALL on_rx(libusb_transfer* t) {
    auto* self = static_cast<UsbHostTransport*>(t->user_data);
    self->rx_pending_ = false;
    if (self->completed_) *self->completed_ = 1;
    if (t->status == LIBUSB_TRANSFER_COMPLETED) {
      self->rx_len_ = static_cast<size_t>(t->actual_length), self->rx_pos_ = 0;
      if (self->rx_len_ == 0) (void)self->submit_read();  // zero-length packet
    } else if (t->status != LIBUSB_TRANSFER_CANCELLED) {
      self->fail("bulk IN:", t->status);
    }
  }

  static void LIBUSB_CALL on_tx(libusb_transfer* t) {
    auto* self = static_cast<UsbHostTransport*>(t->user_data);
    self->tx_pending_ = false;
    if (self->completed_) *self->completed_ = 1;
    if (t->status != LIBUSB_TRANSFER_COMPLETED && t->status != LIBUSB_TRANSFER_CANCELLED)
      self->fail("bulk OUT:", t->status);
  }

  UsbSelector selector_;
  std::string name_;
  std::mutex context_mutex_;  // interrupt() may come from another thread while open() renews it
  libusb_context* context_ = nullptr;
  int init_rc_ = 0;
  libusb_device_handle* handle_ = nullptr;
  int interface_ = -1;
  uint8_t in_endpoint_ = 0, out_endpoint_ = 0;
  libusb_transfer* rx_transfer_ = nullptr;
  libusb_transfer* tx_transfer_ = nullptr;
  bool rx_pending_ = false, tx_pending_ = false, failed_ = false;
  int* completed_ = nullptr;
  char failure_[96] = {};
  unsigned char rx_[kUsbMaxTransfer];
  unsigned char tx_[kUsbMaxTransfer];
  size_t rx_len_ = 0, rx_pos_ = 0;
};

}  // namespace

Result<std::unique_ptr<transport::Transport>> make_usb_host_transport(const UsbSelector& selector) {
  return std::unique_ptr<transport::Transport>(std::make_unique<UsbHostTransport>(selector));
}

}  // namespace tlvlink::listen
