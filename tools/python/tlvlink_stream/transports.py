"""The links a host reads the stream from: a serial device (pyserial: a UART, /dev/ttyACM0, a
pty) or the board's USB bulk interface (pyusb). Both: open() raises LinkUnavailable while the
device is absent; read/write raise LinkLost when it goes away (the Client reopens it)."""

from __future__ import annotations

import errno
from dataclasses import dataclass
from typing import List, Optional

USB_INTERFACE = (0xFF, 0x54, 0x01)  # class, subclass, protocol (tlvlink/transport/usb_stream.h)
USB_MAX_TRANSFER = 16384
USB_PAD_MULTIPLE = 64
USB_DEFAULT_IDS = (0x1D6B, 0x0104)


class LinkUnavailable(OSError):
    """The device is not there (yet): try again later."""


class LinkLost(OSError):
    """The device went away while in use."""


class SerialLink:
    def __init__(self, path: str, baud: int = 0, rtscts: bool = False) -> None:
        self.path, self.baud, self.rtscts = path, baud, rtscts
        self.name = f"serial:{path}"
        self._port = None

    def open(self) -> None:
        import serial  # python3-serial
        try:
            self._port = serial.Serial(self.path, baudrate=self.baud or 115200, rtscts=self.rtscts, timeout=0)
        except (serial.SerialException, OSError) as e:
            raise LinkUnavailable(f"opening {self.path}: {e}") from e

    def close(self) -> None:
        if self._port is not None:
            try:
                self._port.close()
            except OSError:
                pass
        self._port = None

    @property
    def is_open(self) -> bool:
        return self._port is not None

    def read(self, timeout: float) -> bytes:
        import serial
        try:
            self._port.timeout = max(timeout, 0.0)
            first = self._port.read(1)
            if not first:
                return b""
            waiting = self._port.in_waiting
            return first + (self._port.read(waiting) if waiting else b"")
        except (serial.SerialException, OSError) as e:
            raise LinkLost(f"{self.name}: {e}") from e

    def write(self, data: bytes) -> None:
        import serial
        try:
            self._port.write(data)
        except (serial.SerialException, OSError) as e:
            raise LinkLost(f"{self.name}: {e}") from e


@dataclass
class UsbCandidate:
    vendor: int
    product: int
    serial: str = ""
    bus: int = 0
    address: int = 0
    has_stream_interface: bool = False
    accessible: bool = True


def select_usb_device(found: List[UsbCandidate], vendor: int, product: int, serial: str = "") -> int:
    """Index of the one board to use (the C++ select_usb_device's rules); LinkUnavailable or
    ValueError naming what was found otherwise."""
    seen, chosen = [], []
    for i, c in enumerate(found):
        if (c.vendor, c.product) != (vendor, product):
            continue
        text = f"{c.vendor:04x}:{c.product:04x} on bus {c.bus} address {c.address}, serial '{c.serial}'"
        if not c.accessible:
            seen.append(text + " (no permission: install the udev rule or run as root)")
            continue
        if serial and c.serial != serial:
            seen.append(text)
            continue
        if not c.has_stream_interface:
            seen.append(text + " (no tlvlink stream interface: is tlvlinkd running with output \"usb\"?)")
            continue
        seen.append(text)
        chosen.append(i)
    head = f"USB {vendor:04x}:{product:04x}" + (f" serial {serial}" if serial else "")
    if len(chosen) == 1:
        return chosen[0]
    if len(chosen) > 1:
        raise ValueError(f"{head}: {len(chosen)} boards match ({'; '.join(seen)}); choose one with serial=")
    raise LinkUnavailable(f"{head}: no board with the stream interface found" + (f"; seen: {'; '.join(seen)}" if seen else ""))


class UsbLink:
    def __init__(self, vendor: int = USB_DEFAULT_IDS[0], product: int = USB_DEFAULT_IDS[1], serial: str = "") -> None:
        self.vendor, self.product, self.serial = vendor, product, serial
        self.name = f"usb:{vendor:04x}:{product:04x}" + (f",serial={serial}" if serial else "")
        self._dev = None
        self._in = self._out = None
        self._interface = None

    @property
    def is_open(self) -> bool:
        return self._dev is not None

    def _stream_interface(self, dev):
        try:
            config = dev.get_active_configuration()
        except Exception:  # noqa: BLE001 - unconfigured or inaccessible device
            return None
        for intf in config:
            if (intf.bInterfaceClass, intf.bInterfaceSubClass, intf.bInterfaceProtocol) == USB_INTERFACE:
                return intf
        return None

    def open(self) -> None:
        try:
            import usb.core  # python3-usb
            import usb.util
        except ImportError as e:
            raise LinkUnavailable("USB links need pyusb (Debian: python3-usb)") from e
        try:
            devices = list(usb.core.find(find_all=True, idVendor=self.vendor, idProduct=self.product))
        except usb.core.NoBackendError as e:
            raise LinkUnavailable(f"pyusb has no backend (Debian: libusb-1.0-0): {e}") from e
        found = []
        for dev in devices:
            c = UsbCandidate(dev.idVendor, dev.idProduct, bus=dev.bus or 0, address=dev.address or 0)
            try:
                c.serial = dev.serial_number or ""
            except (ValueError, usb.core.USBError):
                c.accessible = False
            c.has_stream_interface = self._stream_interface(dev) is not None
            found.append(c)
        dev = devices[select_usb_device(found, self.vendor, self.product, self.serial)]
        intf = self._stream_interface(dev)
        try:
            if dev.is_kernel_driver_active(intf.bInterfaceNumber):
                dev.detach_kernel_driver(intf.bInterfaceNumber)
            usb.util.claim_interface(dev, intf.bInterfaceNumber)
        except usb.core.USBError as e:
            raise LinkUnavailable(f"claiming the stream interface of {self.name} (another reader?): {e}") from e
        for ep in intf:
            if usb.util.endpoint_type(ep.bmAttributes) != usb.util.ENDPOINT_TYPE_BULK:
                continue
            if usb.util.endpoint_direction(ep.bEndpointAddress) == usb.util.ENDPOINT_IN:
                self._in = ep.bEndpointAddress
            else:
                self._out = ep.bEndpointAddress
        self._dev, self._interface = dev, intf.bInterfaceNumber

    def close(self) -> None:
        if self._dev is None:
            return
        import usb.util
        try:
            usb.util.release_interface(self._dev, self._interface)
            usb.util.dispose_resources(self._dev)
        except Exception:  # noqa: BLE001 - the device may be gone already
            pass
        self._dev = None

    def read(self, timeout: float) -> bytes:
        import usb.core
        try:
            return bytes(self._dev.read(self._in, USB_MAX_TRANSFER, timeout=max(1, int(timeout * 1000))))
        except usb.core.USBTimeoutError:
            return b""
        except usb.core.USBError as e:
            if e.errno in (errno.ETIMEDOUT,):
                return b""
            raise LinkLost(f"{self.name}: {e}") from e

    def write(self, data: bytes) -> None:
        import usb.core
        # Transfers of at most 16383 bytes; one that ends on a full packet gets a 0x00 (an empty
        # frame to the reader) so it ends short and completes at once (usb_stream.h).
        try:
            for i in range(0, len(data), USB_MAX_TRANSFER - 1):
                chunk = data[i:i + USB_MAX_TRANSFER - 1]
                if len(chunk) % USB_PAD_MULTIPLE == 0:
                    chunk += b"\x00"
                self._dev.write(self._out, chunk, timeout=1000)
        except usb.core.USBError as e:
            raise LinkLost(f"{self.name}: {e}") from e


def open_source(source: str):
    """A link from a source string: serial:PATH[,baud=N][,flow=none|rtscts] or
    usb[:VID:PID][,serial=S]. ValueError for a malformed one."""
    scheme, _, rest = source.partition(":")
    if "," in scheme:
        scheme, _, more = scheme.partition(",")
        rest = "," + more
    if scheme == "serial":
        path, *options = rest.split(",")
        if not path:
            raise ValueError("serial: needs a device path (serial:/dev/ttyACM0)")
        baud, rtscts = 0, False
        for o in options:
            key, _, value = o.partition("=")
            if key == "baud" and value.isdigit():
                baud = int(value)
            elif key == "flow" and value in ("none", "rtscts"):
                rtscts = value == "rtscts"
            else:
                raise ValueError(f"source '{source}': bad option '{o}' (baud=N, flow=none|rtscts)")
        return SerialLink(path, baud, rtscts)
    if scheme == "usb":
        ids, *options = rest.split(",") if rest else [""]
        vendor, product = USB_DEFAULT_IDS
        if ids:
            v, sep, p = ids.partition(":")
            try:
                vendor, product = int(v, 16), int(p, 16)
            except ValueError:
                sep = ""
            if not sep or not (0 <= vendor <= 0xFFFF and 0 <= product <= 0xFFFF):
                raise ValueError(f"usb '{rest}': expected VID:PID (e.g. 1d6b:0104)")
        serial = ""
        for o in options:
            if not o.startswith("serial="):
                raise ValueError(f"usb '{rest}': unknown option '{o}' (serial=S)")
            serial = o[len("serial="):]
        return UsbLink(vendor, product, serial)
    raise ValueError(f"source '{source}': expected serial:PATH[,baud=N][,flow=rtscts], usb[:VID:PID][,serial=S] "
                     f"or replay:FILE")
