#include "frame_images.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>

#include "clock.h"
#include "tlvlink/log.h"
#include "tlvlink/protocol/encode.h"

namespace tlvlink::daemon::internal {
namespace {

TLV_LOG_CATEGORY(kLogImages, "images");

constexpr int32_t kMinQuality = 20;  // re-encoding to fit stops here
constexpr int kEncoderNice = 10;     // the encoder thread yields to capture, inference and link

// Bits per pixel a baseline 4:2:0 JPEG of a gel image stays under, by quality band. Measured on
// the simulated GelSight Mini scenario (tools/bench/frame_images_latency.sh): the 320x240 view at
// quality 70 takes 0.26 bpp at the median, 0.33 at most (2.5 / 3.2 KB); the bound is ~4x that,
// room for real camera noise and sharp imprints, so a configuration that passes fits in practice
// and one that could fit only on a quiet gel is refused.
double bits_per_pixel(int32_t quality) {
  if (quality <= 50) return 1.0;
  if (quality <= 75) return 1.5;
  if (quality <= 90) return 2.5;
  return 4.0;
}

size_t mask_bytes(int32_t cells) { return (static_cast<size_t>(cells) + 7) / 8; }

// The contact gate's grid as a FrameImage carries it (at most 255 cells a side; none beyond).
bool mask_on_wire(const pipeline::ContactGate& g) {
  return g.grid_width() <= 255 && g.grid_height() <= 255;
}

}  // namespace

ImageSize frame_image_size(int32_t width, int32_t height, int32_t max_side) {
  const int32_t side = std::max(width, height);
  if (side <= max_side) return {width, height};
  return {std::max(1, static_cast<int32_t>(static_cast<int64_t>(width) * max_side / side)),
          std::max(1, static_cast<int32_t>(static_cast<int64_t>(height) * max_side / side))};
}

Status check_frame_image_fits(int32_t width, int32_t height, int32_t quality, int32_t mask_cells,
                              const char* key) {
  const size_t budget =
      protocol::kMaxPayloadSize - protocol::frame_image_overhead(mask_bytes(mask_cells));
  const double bound = static_cast<double>(width) * height * bits_per_pixel(quality) / 8;
  TLV_ENSURE(bound <= static_cast<double>(budget), ErrorCode::kInvalidArgument,
             "%s: a %dx%d JPEG at quality %d may take up to %.0f bytes; a FrameImage carries %zu "
             "(lower frame_image_max_side or frame_image_quality)",
             key, width, height, quality, bound, budget);
  return {};
}

Result<std::unique_ptr<FrameImages>> FrameImages::create(
    const DaemonConfig& config, std::span<const pipeline::SensorSetup> setups,
    const pipeline::FrameProcessor& processor, Post post) {
  auto f = std::unique_ptr<FrameImages>(new FrameImages(processor, std::move(post)));
  f->input_ = config.frame_images == FrameImageKind::kInput;
  f->quality_ = config.frame_image_quality;
  f->max_side_ = config.frame_image_max_side;
  f->period_ns_ = 1'000'000'000 / config.frame_images_per_second;
  size_t pixels = 0, mask = 0;
  for (size_t i = 0; i < setups.size(); ++i) {
    const auto sensor = static_cast<int32_t>(i);
    ImageSize size = frame_image_size(setups[i].width, setups[i].height, f->max_side_);
    if (f->input_) size = {processor.plan(sensor).width(), processor.plan(sensor).height()};
    const pipeline::ContactGate& g = processor.gate(sensor);
    const int32_t cells = mask_on_wire(g) ? g.grid_width() * g.grid_height() : 0;
    // The model's input size is known only now: checked as the configuration's view was.
    TLV_TRY(
        check_frame_image_fits(size.width, size.height, f->quality_, cells,
                               f->input_ ? "frame_images = \"input\"" : "frame_image_max_side"));
    pixels = std::max(pixels, static_cast<size_t>(size.width) * static_cast<size_t>(size.height) *
                                  static_cast<size_t>(setups[i].channels));
    mask = std::max(mask, mask_bytes(cells));
  }
  for (size_t i = 0; i < kSlots; ++i) {
    f->slots_[i].pixels.resize(pixels);
    f->slots_[i].mask.resize(mask);
    f->free_.push(static_cast<uint8_t>(i));
  }
  // The encoder's buffer (tjBufSize of the largest image) is allocated by its first encode.
  for (size_t i = 0; i < setups.size(); ++i) {
    const ImageSize size = f->input_
                               ? ImageSize{processor.plan(static_cast<int32_t>(i)).width(),
                                           processor.plan(static_cast<int32_t>(i)).height()}
                               : frame_image_size(setups[i].width, setups[i].height, f->max_side_);
    const image::ImageView blank{f->slots_[0].pixels.data(), size.width, size.height,
                                 setups[i].channels, 0};
    auto warm = f->encoder_.encode(blank, f->quality_,
                                   setups[i].channels == 1 ? image::JpegEncoder::Subsampling::kGray
                                                           : image::JpegEncoder::Subsampling::k420);
    if (!warm.ok())
      return warm.error().with_context("frame images of sensor '%s'", setups[i].name.c_str());
  }
  return f;
}

void FrameImages::fill(Slot& slot, int32_t sensor, const image::ImageView& frame) {
  slot.channels = frame.channels;
  if (input_) {
    // What the model sees: its crop and resize, as uint8 pixels before normalisation.
    const image::PreprocessPlan& plan = processor_.plan(sensor);
    slot.width = plan.width();
    slot.height = plan.height();
    const size_t n = static_cast<size_t>(slot.width) * static_cast<size_t>(slot.height) *
                     static_cast<size_t>(slot.channels);
    if (!plan.resize(frame, std::span<uint8_t>(slot.pixels).first(n)).ok()) slot.width = 0;
  } else {
    // The view, nearest-neighbour down to max_side: a copy of at most max_side^2 pixels.
    const ImageSize size = frame_image_size(frame.width, frame.height, max_side_);
    slot.width = size.width;
    slot.height = size.height;
    const auto ch = static_cast<size_t>(frame.channels);
    uint8_t* out = slot.pixels.data();
    for (int32_t y = 0; y < size.height; ++y) {
      const uint8_t* row =
          frame.row(static_cast<int32_t>(static_cast<int64_t>(y) * frame.height / size.height));
      for (int32_t x = 0; x < size.width; ++x) {
        const uint8_t* p =
            row + static_cast<size_t>(static_cast<int64_t>(x) * frame.width / size.width) * ch;
        for (size_t c = 0; c < ch; ++c) *out++ = p[c];
      }
    }
  }
  const pipeline::ContactGate& g = processor_.gate(sensor);
  if (mask_on_wire(g)) {
    slot.mask_width = g.grid_width();
    slot.mask_height = g.grid_height();
    if (!g.contact_mask(
              std::span<uint8_t>(slot.mask).first(mask_bytes(slot.mask_width * slot.mask_height)))
             .ok())
      slot.mask_width = slot.mask_height = 0;
  } else {
    slot.mask_width = slot.mask_height = 0;
  }
}

void FrameImages::offer(int32_t sensor, uint64_t sequence, int64_t capture_ns,
                        const image::ImageView& frame, bool contact) {
  int64_t& due = next_due_ns_[static_cast<size_t>(sensor)];
  if (capture_ns < due) return;  // the frame loop's whole cost while no image is due
  // The next one a period on, on the capture clock; after a pause, a period from now.
  due = due + period_ns_ > capture_ns ? due + period_ns_ : capture_ns + period_ns_;
  uint8_t i = 0;
  {
    std::lock_guard lock(mutex_);
    if (!free_.pop(i)) {
      if (!ready_.pop(i)) return;  // cannot happen with kSlots = 3 (one encoding at most)
      busy_.fetch_add(1);          // the oldest waiting image gives way
    }
  }
  const int64_t t0 = board_clock_ns();
  Slot& slot = slots_[i];
  slot.sensor = sensor;
  slot.sequence = sequence;
  slot.capture_ns = capture_ns;
  slot.contact = contact;
  fill(slot, sensor, frame);
  copy_ns_.fetch_add(board_clock_ns() - t0);
  copies_.fetch_add(1);
  {
    std::lock_guard lock(mutex_);
    ready_.push(i);
  }
  wake_.notify_one();
}

void FrameImages::encode_and_post(const Slot& slot) {
  if (slot.width == 0) return;
  const image::ImageView view{slot.pixels.data(), slot.width, slot.height, slot.channels, 0};
  const auto subsampling = slot.channels == 1 ? image::JpegEncoder::Subsampling::kGray
                                              : image::JpegEncoder::Subsampling::k420;
  const size_t mask = mask_bytes(slot.mask_width * slot.mask_height);
  const size_t budget = protocol::kMaxPayloadSize - protocol::frame_image_overhead(mask);
  // The configured quality, lower only when a busy image does not fit.
  for (int32_t q = quality_; q >= kMinQuality; q = q * 3 / 4) {
    Result<std::span<const uint8_t>> jpeg = encoder_.encode(view, q, subsampling);
    if (!jpeg.ok()) {
      TLV_LOG(kLogImages, kWarning, "%s", jpeg.error().message());
      break;
    }
    if (jpeg.value().size() > budget) continue;
    stream::FrameImageRecord r;
    r.sensor = slot.sensor;
    r.sequence = slot.sequence;
    r.capture_ns = slot.capture_ns;
    r.input = input_;
    r.width = slot.width;
    r.height = slot.height;
    r.contact = slot.contact;
    r.mask_width = slot.mask_width;
    r.mask_height = slot.mask_height;
    r.mask = std::span<const uint8_t>(slot.mask).first(mask);
    r.jpeg = jpeg.value();
    (post_(r) ? sent_ : busy_).fetch_add(1);
    return;
  }
  busy_.fetch_add(1);
}

void FrameImages::run(const std::atomic<bool>& stop) {
  // Linux: a thread's nice value is its own (setpriority on its thread id).
  [[maybe_unused]] const int r =
      setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), kEncoderNice);
  while (!stop.load()) {
    uint8_t i = 0;
    {
      std::unique_lock lock(mutex_);
      wake_.wait_for(lock, std::chrono::milliseconds(100),
                     [&] { return !ready_.empty() || stop.load(); });
      if (!ready_.pop(i)) continue;
    }
    const int64_t t0 = board_clock_ns();
    encode_and_post(slots_[i]);
    encode_ns_.fetch_add(board_clock_ns() - t0);
    encodes_.fetch_add(1);
    {
      std::lock_guard lock(mutex_);
      free_.push(i);
    }
  }
}

}  // namespace tlvlink::daemon::internal
