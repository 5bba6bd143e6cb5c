#pragma once
// Internals of the libcamera source: the completion ring between libcamera's thread and next(),
// the camera session (libcamera objects, only in libcamera_camera.cc), and the source's state.
#ifndef TLVLINK_CAPTURE_PRIVATE
#error "runtime/capture internal header: include tlvlink/capture/libcamera_source.h instead"
#endif

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "tlvlink/capture/frame_accounting.h"
#include "tlvlink/capture/libcamera_source.h"
#include "tlvlink/capture/reconnect_backoff.h"
#include "tlvlink/drop_oldest_ring.h"

namespace tlvlink::capture::internal {

inline constexpr uint32_t kMaxCompletions =
    8;  // >= buffers in flight: each completes once per queue

// Completed buffers, pushed by libcamera's thread (or a test), popped by next(). A drop-oldest
// ring over fixed storage, a mutex held for a copy, an eventfd to wake a waiting next().
class Completions {
 public:
  Completions();
  ~Completions();
  bool ok() const { return efd_ >= 0; }
  void push(const LibcameraCompletion& c);
  void wake();  // e.g. a disconnect: next() looks at the session state
  bool pop(LibcameraCompletion& c);
  // Waits until something was pushed or woken, at most timeout_ms; false on timeout.
  bool wait(int timeout_ms);
  void clear();

 private:
  std::mutex mu_;
  std::array<LibcameraCompletion, kMaxCompletions> storage_{};
  DropOldestRing<LibcameraCompletion> ring_{storage_};
  int efd_ = -1;
};

// An acquired, configured and started camera (libcamera objects inside).
class CameraSession {
 public:
  virtual ~CameraSession() = default;
  virtual void requeue(uint32_t buffer) = 0;
  virtual bool disconnected() const = 0;
  image::FrameFormat format;
  double nominal_fps = 0;
  std::vector<std::span<const uint8_t>> buffers;  // mapped read-only
  char camera[128] = {};                          // id, for the source's name
};

// Opens the camera of `config`; completions go to `sink`. Errors name the camera and the step.
Result<std::unique_ptr<CameraSession>> open_camera(const LibcameraConfig& config, const char* label,
                                                   Completions& sink);

}  // namespace tlvlink::capture::internal

namespace tlvlink::capture {

struct LibcameraSource::State {
  explicit State(const LibcameraConfig& c)
      : config(c), backoff(c.backoff_initial_ms, c.backoff_max_ms) {}

  LibcameraConfig config;
  char name[192] = {};
  SourceStats stats;
  FrameAccounting accounting{stats};
  image::FrameFormat format;
  internal::Completions completions;
  std::unique_ptr<internal::CameraSession> session;  // null in test mode
  std::vector<std::span<const uint8_t>> test_buffers;
  bool test_mode = false;
  bool started = false;
  int held = -1;
  std::atomic<uint64_t> requeued{0};
  // Outage (a camera that disconnected).
  bool streamed = false;  // a frame was delivered since the camera was opened
  ReconnectBackoff backoff;
  Error last_reopen_error;

  std::span<const uint8_t> buffer(uint32_t i) const {
    const auto& b = session ? session->buffers : test_buffers;
    return i < b.size() ? b[i] : std::span<const uint8_t>();
  }
  void requeue(uint32_t i) {
    ++requeued;
    if (session) session->requeue(i);
  }
};

}  // namespace tlvlink::capture
