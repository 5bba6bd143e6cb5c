#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "frame_images.h is internal to firmware/tlvlinkd"
#endif
// FrameImages on the stream link (protocol 1.2, runtime/protocol/README.md section 6a): a
// rate-limited JPEG of a sensor's decoded view or of the model's input, with the contact gate's
// mask. The frame loop pays one comparison per frame; when an image is due (a rate limiter on
// the capture clock) the inference thread copies the small image into a preallocated slot and
// goes on. A thread of its own, at a lower priority, encodes the JPEG into the encoder's
// preallocated buffer and posts it; slots are handed through drop-oldest rings, so a slow
// encoder costs the oldest waiting image, counted (image_busy) like an image the link was too
// busy to take.

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "tlvlink/daemon/config.h"
#include "tlvlink/drop_oldest_ring.h"
#include "tlvlink/error.h"
#include "tlvlink/image/image.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/pipeline/frame_processor.h"
#include "tlvlink/stream/message_mapper.h"

namespace tlvlink::daemon::internal {

// The size an image of w x h is sent at: scaled down to fit max_side (never up).
struct ImageSize {
  int32_t width = 0, height = 0;
};
ImageSize frame_image_size(int32_t width, int32_t height, int32_t max_side);

// Refuses (kInvalidArgument naming `key`) an image of w x h at `quality` whose JPEG could
// exceed what a FrameImage carries beside a mask of `mask_cells`: the bound is a conservative
// bits-per-pixel figure per quality band (frame_images.cc), so a configuration that passes
// fits on every frame in practice; a frame that still does not is re-encoded at lower quality.
Status check_frame_image_fits(int32_t width, int32_t height, int32_t quality, int32_t mask_cells,
                              const char* key);

class FrameImages {
 public:
  // Posts one encoded image; false when the link is busy (the image is dropped and counted).
  // Called on the encoder thread.
  using Post = std::function<bool(const stream::FrameImageRecord&)>;

  // Borrows `processor` (its plans and gates) for its lifetime; allocates every slot and warms
  // the JPEG encoder up here.
  static Result<std::unique_ptr<FrameImages>> create(const DaemonConfig& config,
                                                     std::span<const pipeline::SensorSetup> setups,
                                                     const pipeline::FrameProcessor& processor,
                                                     Post post);

  // The inference thread, after processing `frame` of `sensor`: one comparison unless an image
  // is due. No allocation.
  void offer(int32_t sensor, uint64_t sequence, int64_t capture_ns, const image::ImageView& frame,
             bool contact);
  // The encoder thread: returns when `stop` is set (images still waiting are not sent).
  void run(const std::atomic<bool>& stop);

  uint64_t busy() const { return busy_.load(); }  // image_busy: dropped in a slot or by the link
  uint64_t sent() const { return sent_.load(); }
  // Time spent per image: copying it on the inference thread, encoding it on the encoder thread
  // (board clock, summed; two clock reads per image, none per frame).
  int64_t copy_ns() const { return copy_ns_.load(); }
  int64_t encode_ns() const { return encode_ns_.load(); }
  uint64_t copies() const { return copies_.load(); }
  uint64_t encodes() const { return encodes_.load(); }

 private:
  static constexpr size_t kSlots = 3;  // one encoding, one waiting, one being filled
  struct Slot {
    int32_t sensor = 0;
    uint64_t sequence = 0;
    int64_t capture_ns = 0;
    bool contact = false;
    int32_t width = 0, height = 0, channels = 3;
    std::vector<uint8_t> pixels;  // the largest image of any sensor
    std::vector<uint8_t> mask;    // the largest mask of any sensor
    int32_t mask_width = 0, mask_height = 0;
  };
  FrameImages(const pipeline::FrameProcessor& processor, Post post)
      : processor_(processor),
        post_(std::move(post)),
        free_(free_storage_),
        ready_(ready_storage_) {}
  void fill(Slot& slot, int32_t sensor, const image::ImageView& frame);
  void encode_and_post(const Slot& slot);

  const pipeline::FrameProcessor& processor_;
  Post post_;
  bool input_ = false;
  int32_t quality_ = 70, max_side_ = 320;
  int64_t period_ns_ = 0;
  std::array<int64_t, pipeline::kMaxSensors> next_due_ns_{};  // inference thread only
  std::array<Slot, kSlots> slots_;
  std::array<uint8_t, kSlots> free_storage_{}, ready_storage_{};
  std::mutex mutex_;  // guards the two rings
  std::condition_variable wake_;
  DropOldestRing<uint8_t> free_, ready_;  // slot indices
  image::JpegEncoder encoder_;            // encoder thread only (after create's warm-up)
  std::atomic<uint64_t> busy_{0}, sent_{0}, copies_{0}, encodes_{0};
  std::atomic<int64_t> copy_ns_{0}, encode_ns_{0};
};

}  // namespace tlvlink::daemon::internal
