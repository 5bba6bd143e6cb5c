#include "tlvlink/error.h"

#include <cstdarg>
#include <cstdio>
#include <cstring>

namespace tlvlink {
namespace {

// Formats into a fixed buffer; an over-long message ends in "..." rather than being cut silently.
// The format attribute lets clang check the callers' literal formats instead of this forward.
[[gnu::format(printf, 2, 0)]] void format_into(char (&out)[Error::kMaxErrorMessage + 1],
                                               const char* format, va_list args) {
  const int n = std::vsnprintf(out, sizeof(out), format, args);
  if (n > static_cast<int>(Error::kMaxErrorMessage)) {
    std::memcpy(out + Error::kMaxErrorMessage - 3, "...", 4);
  }
}

}  // namespace

Error::Error(ErrorCode code, const char* message) : code_(code) {
  std::snprintf(message_, sizeof(message_), "%s", message);
}

Error Error::make(ErrorCode code, const char* format, ...) {
  Error e;
  e.code_ = code;
  va_list args;
  va_start(args, format);
  format_into(e.message_, format, args);
  va_end(args);
  return e;
}

Error Error::with_context(const char* format, ...) const {
  Error e;
  e.code_ = code_;
  char prefix[kMaxErrorMessage + 1];
  va_list args;
  va_start(args, format);
  format_into(prefix, format, args);
  va_end(args);
  const int n = std::snprintf(e.message_, sizeof(e.message_), "%s: %s", prefix, message_);
  if (n > static_cast<int>(kMaxErrorMessage))
    std::memcpy(e.message_ + kMaxErrorMessage - 3, "...", 4);
  return e;
}

const char* error_code_name(ErrorCode code) {
  switch (code) {
    case ErrorCode::kOk: return "ok";
    case ErrorCode::kModelMalformed: return "model.malformed";
    case ErrorCode::kModelVersion: return "model.version";
    case ErrorCode::kModelInvalidTensor: return "model.invalid_tensor";
    case ErrorCode::kModelInvalidOperator: return "model.invalid_operator";
    case ErrorCode::kModelInvalidMetadata: return "model.invalid_metadata";
    case ErrorCode::kModelChecksum: return "model.checksum";
    case ErrorCode::kModelUnsupported: return "model.unsupported";
    case ErrorCode::kModelSignature: return "model.signature";
    case ErrorCode::kBackend: return "runtime.backend";
    case ErrorCode::kNonFiniteValue: return "runtime.non_finite";
    case ErrorCode::kShapeMismatch: return "runtime.shape_mismatch";
    case ErrorCode::kOutOfMemory: return "runtime.out_of_memory";
    case ErrorCode::kInvalidState: return "runtime.invalid_state";
    case ErrorCode::kInvalidArgument: return "io.invalid_argument";
    case ErrorCode::kIo: return "io.error";
    case ErrorCode::kFormat: return "io.format";
    case ErrorCode::kCapture: return "capture.device";
    case ErrorCode::kCaptureNoDevice: return "capture.no_device";
    case ErrorCode::kCaptureNotCamera: return "capture.not_camera";
    case ErrorCode::kCaptureDisconnected: return "capture.disconnected";
    case ErrorCode::kCaptureTimeout: return "capture.timeout";
    case ErrorCode::kCaptureFormatRefused: return "capture.format_refused";
    case ErrorCode::kCaptureBadFrame: return "capture.bad_frame";
    case ErrorCode::kCaptureControl: return "capture.control";
    case ErrorCode::kCaptureEndOfStream: return "capture.end_of_stream";
    case ErrorCode::kTransport: return "transport";
    case ErrorCode::kTransportUnavailable: return "transport.unavailable";
    case ErrorCode::kTransportDisconnected: return "transport.disconnected";
    case ErrorCode::kProtocolMalformed: return "protocol.malformed";
    case ErrorCode::kProtocolVersion: return "protocol.version";
    case ErrorCode::kProtocolTooLarge: return "protocol.too_large";
    case ErrorCode::kProtocolUnsupported: return "protocol.unsupported";
  }
  return "unknown";
}

}  // namespace tlvlink
