#pragma once
// tlvlink's single error vocabulary: an ErrorCode grouped by area, an Error carrying a
// human-readable message that says what failed, where and why, and Result<T> / Status.
// No exceptions, no heap: the message lives in a fixed buffer so errors can be raised in the
// per-frame path without allocating. Messages longer than kMaxErrorMessage are cut with "...".

#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>

namespace tlvlink {

enum class ErrorCode : uint16_t {
  kOk = 0,
  // Model file (untrusted input): 100s.
  kModelMalformed = 100,  // not a flatbuffer / verifier failed / wrong identifier
  kModelVersion,          // schema version this runtime does not read
  kModelInvalidTensor,    // a tensor's shape, dtype, quantization or data is inconsistent
  kModelInvalidOperator,  // an operator's inputs, outputs or options are inconsistent
  kModelInvalidMetadata,  // input spec, heads or provenance inconsistent
  kModelChecksum,         // the file's bytes do not match its recorded hash (or it has none)
  kModelUnsupported,      // valid model using something this build cannot execute
  kModelSignature,        // a signature is required and is absent, by another key, or wrong
  // Runtime / executors: 200s.
  kBackend = 200,   // XNNPACK (or another backend) refused or failed
  kNonFiniteValue,  // NaN/Inf in a float input or output
  kShapeMismatch,   // caller passed a tensor of the wrong size/shape
  kOutOfMemory,
  kInvalidState,  // call order violated (e.g. invoke before inputs set)
  // Host I/O and arguments: 300s.
  kInvalidArgument = 300,
  kIo,      // file could not be opened/read/written
  kFormat,  // a data file (npy, image) is malformed
  // Capture (frame sources, runtime/capture): 400s.
  kCapture = 400,         // a failed device call not covered below (ioctl/mmap errno)
  kCaptureNoDevice,       // no device matches the selector (absent, unplugged, other serial)
  kCaptureNotCamera,      // the node is not a video capture device (metadata/output node, not V4L2)
  kCaptureDisconnected,   // the device went away (ENODEV, POLLHUP, watchdog); reconnecting
  kCaptureTimeout,        // no frame within the caller's timeout
  kCaptureFormatRefused,  // pixel format, size, interval or buffer count not what was asked
  kCaptureBadFrame,       // flagged, empty or short frame, MJPEG without SOI/EOI
  kCaptureControl,        // a camera control is unknown, out of range or refused
  kCaptureEndOfStream,    // a replayed source played its last frame (no loop): no more frames
  // Stream link: transports (runtime/transport) 500-509, protocol (runtime/protocol) 510-519.
  kTransport = 500,          // I/O on the link failed
  kTransportUnavailable,     // device, path or USB host absent now: retry later
  kTransportDisconnected,    // the link went away while in use (hangup, unbind, unplug)
  kProtocolMalformed = 510,  // a frame or payload that does not decode (framing, CRC, schema)
  kProtocolVersion,          // the peer speaks an incompatible major protocol version
  kProtocolTooLarge,         // a message larger than the frame or buffer it must fit
  kProtocolUnsupported,      // a command or message this side does not implement
};

// Short stable name of a code, e.g. "model.invalid_tensor".
const char* error_code_name(ErrorCode code);

class Error {
 public:
  static constexpr size_t kMaxErrorMessage = 255;

  Error() = default;
  Error(ErrorCode code, const char* message);

  // printf-style constructor; the format is checked by the compiler.
  [[gnu::format(printf, 2, 3)]] static Error make(ErrorCode code, const char* format, ...);

  ErrorCode code() const { return code_; }
  const char* message() const { return message_; }

  // Prefixes context, e.g. error.with_context("loading %s", path) -> "loading m.tlvm: <message>".
  [[gnu::format(printf, 2, 3)]] Error with_context(const char* format, ...) const;

 private:
  ErrorCode code_ = ErrorCode::kOk;
  char message_[kMaxErrorMessage + 1] = {};
};

// Outcome of an operation with no value.
class [[nodiscard]] Status {
 public:
  Status() = default;                     // ok
  Status(Error error) : error_(error) {}  // NOLINT: implicit so `return Error::make(...)` works
  static Status ok_status() { return Status(); }

  bool ok() const { return error_.code() == ErrorCode::kOk; }
  explicit operator bool() const { return ok(); }
  const Error& error() const { return error_; }

 private:
  Error error_;
};

// A value or an Error. T must be movable.
template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : has_value_(true) { new (&storage_.value) T(std::move(value)); }  // NOLINT
  Result(Error error) : has_value_(false) { new (&storage_.error) Error(error); }    // NOLINT
  Result(Status status) : Result(status.error()) {}                                  // NOLINT
  Result(Result&& other) noexcept : has_value_(other.has_value_) {
    if (has_value_)
      new (&storage_.value) T(std::move(other.storage_.value));
    else
      new (&storage_.error) Error(other.storage_.error);
  }
  Result(const Result&) = delete;
  Result& operator=(const Result&) = delete;
  Result& operator=(Result&&) = delete;
  ~Result() {
    if (has_value_) storage_.value.~T();
  }

  bool ok() const { return has_value_; }
  explicit operator bool() const { return ok(); }
  const Error& error() const { return storage_.error; }
  Status status() const { return has_value_ ? Status() : Status(storage_.error); }

  // Precondition: ok(). Checked by the caller (TLV_ASSIGN_OR_RETURN does it).
  T& value() & { return storage_.value; }
  const T& value() const& { return storage_.value; }
  T&& value() && { return std::move(storage_.value); }
  T& operator*() & { return storage_.value; }
  T* operator->() { return &storage_.value; }
  const T* operator->() const { return &storage_.value; }

 private:
  union Storage {
    Storage() {}
    ~Storage() {}
    T value;
    Error error;
  } storage_;
  bool has_value_;
};

}  // namespace tlvlink

#define TLV_CONCAT_INNER(a, b) a##b
#define TLV_CONCAT(a, b) TLV_CONCAT_INNER(a, b)

// Returns the error of a Status/Result expression from the enclosing function.
#define TLV_TRY(expr)                                          \
  do {                                                         \
    auto&& tlv_try_result_ = (expr);                           \
    if (!tlv_try_result_.ok()) return tlv_try_result_.error(); \
  } while (0)

// `TLV_ASSIGN_OR_RETURN(auto x, make_x());` declares x from a Result or returns its error.
#define TLV_ASSIGN_OR_RETURN(lhs, expr) \
  TLV_ASSIGN_OR_RETURN_IMPL(TLV_CONCAT(tlv_result_, __LINE__), lhs, expr)
#define TLV_ASSIGN_OR_RETURN_IMPL(tmp, lhs, expr) \
  auto tmp = (expr);                              \
  if (!tmp.ok()) return tmp.error();              \
  lhs = std::move(tmp).value()

// Returns an Error built from a printf format when cond is false.
#define TLV_ENSURE(cond, code, ...)                                  \
  do {                                                               \
    if (!(cond)) return ::tlvlink::Error::make((code), __VA_ARGS__); \
  } while (0)
