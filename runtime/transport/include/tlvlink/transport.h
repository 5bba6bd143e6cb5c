#pragma once
// Umbrella header of the transport component: the link interface, serial / pty / FunctionFS
// links, the transport spec strings ("serial:/dev/ttyGS0", "usb", ...) and the board's Sender.
#include "tlvlink/transport/ffs.h"
#include "tlvlink/transport/pty.h"
#include "tlvlink/transport/send_queue.h"
#include "tlvlink/transport/sender.h"
#include "tlvlink/transport/serial.h"
#include "tlvlink/transport/time.h"
#include "tlvlink/transport/transport.h"
#include "tlvlink/transport/transport_spec.h"
#include "tlvlink/transport/usb_stream.h"
