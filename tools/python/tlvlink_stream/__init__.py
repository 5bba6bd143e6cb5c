"""Python client of the tlvlink prediction stream (runtime/protocol/README.md is the protocol).

    from tlvlink_stream import Client, Command
    with Client("serial:/dev/ttyACM0") as client:
        for msg in client.messages():
            print(msg.to_dict(client.hello_body))

Sources: "serial:PATH[,baud=N][,flow=rtscts]", "usb[:VID:PID][,serial=S]", "replay:FILE"."""

from .client import Client, LinkEvent, LinkStats
from .clock import ClockEstimate, ClockSync
from .commands import Command, parse_command
from .flatbuf import DecodeError
from .messages import Message, decode
from .recording import RecordingReader, RecordingWriter
from .schema import SCHEMA_HASH
from .transports import LinkLost, LinkUnavailable, SerialLink, UsbLink

__all__ = ["Client", "LinkEvent", "LinkStats", "ClockEstimate", "ClockSync", "Command", "parse_command",
           "DecodeError", "Message", "decode", "RecordingReader", "RecordingWriter", "SCHEMA_HASH", "LinkLost",
           "LinkUnavailable", "SerialLink", "UsbLink"]
__version__ = "1.0.0"
