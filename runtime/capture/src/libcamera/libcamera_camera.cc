// The libcamera glue: the process-wide CameraManager, and one camera acquired, configured,
// mapped and started, whose completed requests go to a Completions ring.
#include <sys/mman.h>

#include <libcamera/libcamera.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>

#include "libcamera/libcamera_internal.h"

namespace tlvlink::capture {
namespace internal {
namespace {

namespace lc = libcamera;

// libcamera allows one CameraManager per process: every source shares it; it stops when the
// last user goes.
std::shared_ptr<lc::CameraManager> shared_manager(Error& error) {
  static std::mutex mu;
  static std::weak_ptr<lc::CameraManager> weak;
  std::lock_guard<std::mutex> lock(mu);
  if (auto m = weak.lock()) return m;
  auto m = std::shared_ptr<lc::CameraManager>(new lc::CameraManager(), [](lc::CameraManager* p) {
    p->stop();
    delete p;
  });
  if (int rc = m->start(); rc != 0) {
    error = Error::make(ErrorCode::kCapture, "libcamera %s: CameraManager::start: %s",
                        lc::CameraManager::version().c_str(), std::strerror(-rc));
    return nullptr;
  }
  weak = m;
  return m;
}

bool to_libcamera(image::PixelFormat f, lc::PixelFormat& out) {
  switch (f) {
    case image::PixelFormat::kMjpeg: out = lc::formats::MJPEG; return true;
    case image::PixelFormat::kYuyv: out = lc::formats::YUYV; return true;
    case image::PixelFormat::kNv12: out = lc::formats::NV12; return true;
    case image::PixelFormat::kRgb24: out = lc::formats::BGR888; return true;  // bytes R, G, B
    case image::PixelFormat::kGrey: out = lc::formats::R8; return true;
  }
  return false;
}

class Session final : public CameraSession {
 public:
  ~Session() override { close(); }

  Status open(const LibcameraConfig& c, const char* label, Completions& sink) {
    sink_ = &sink;
    Error err;
    manager_ = shared_manager(err);
    if (!manager_) return err;
    const auto cameras = manager_->cameras();
    if (cameras.empty()) {
      return Error::make(
          ErrorCode::kCaptureNoDevice,
          "%s: libcamera %s found no camera (its pipeline handlers matched no device; "
          "UVC cameras are for the V4L2 source)",
          label, lc::CameraManager::version().c_str());
    }
    if (c.camera_id.empty()) {
      if (cameras.size() > 1) {
        return Error::make(ErrorCode::kInvalidArgument,
                           "%s: libcamera found %zu cameras; set camera_id "
                           "(first: %s)",
                           label, cameras.size(), cameras.front()->id().c_str());
      }
      camera_ = cameras.front();
    } else {
      camera_ = manager_->get(c.camera_id);
      if (!camera_) {
        return Error::make(ErrorCode::kCaptureNoDevice,
                           "%s: libcamera has no camera '%s' (first present: %s)", label,
                           c.camera_id.c_str(), cameras.front()->id().c_str());
      }
    }
    std::snprintf(camera, sizeof(camera), "%s", camera_->id().c_str());
    if (int rc = camera_->acquire(); rc != 0) {
      camera_.reset();
      return Error::make(ErrorCode::kCapture, "%s: acquire %s: %s", label, camera,
                         std::strerror(-rc));
    }
    acquired_ = true;
    camera_->disconnected.connect(this, &Session::on_disconnected);
    camera_->requestCompleted.connect(this, &Session::on_completed);
    TLV_TRY(configure(c, label));
    TLV_TRY(allocate(c, label));
    lc::ControlList controls(lc::controls::controls);
    if (c.fps > 0) {
      const int64_t us = std::llround(1e6 / c.fps);
      controls.set(lc::controls::FrameDurationLimits, lc::Span<const int64_t, 2>({us, us}));
      nominal_fps = c.fps;
    }
    if (int rc = camera_->start(&controls); rc != 0) {
      return Error::make(ErrorCode::kCapture, "%s: start %s: %s", label, camera,
                         std::strerror(-rc));
    }
    started_ = true;
    for (auto& r : requests_) {
      if (int rc = camera_->queueRequest(r.get()); rc != 0) {
        return Error::make(ErrorCode::kCapture, "%s: queueRequest: %s", label, std::strerror(-rc));
      }
    }
    return Status();
  }

  void requeue(uint32_t buffer) override {
    if (buffer >= requests_.size() || disconnected_.load()) return;
    requests_[buffer]->reuse(lc::Request::ReuseBuffers);
    camera_->queueRequest(requests_[buffer].get());
  }

  bool disconnected() const override { return disconnected_.load(); }

 private:
  Status configure(const LibcameraConfig& c, const char* label) {
    config_ = camera_->generateConfiguration({lc::StreamRole::VideoRecording});
    if (!config_ || config_->empty()) {
      return Error::make(ErrorCode::kCaptureFormatRefused, "%s: %s offers no video stream", label,
                         camera);
    }
    lc::StreamConfiguration& s = config_->at(0);
    lc::PixelFormat want;
    to_libcamera(c.format, want);
    s.pixelFormat = want;
    s.size = lc::Size(static_cast<unsigned>(c.width), static_cast<unsigned>(c.height));
    s.bufferCount = c.buffers;
    if (config_->validate() == lc::CameraConfiguration::Invalid) {
      return Error::make(ErrorCode::kCaptureFormatRefused, "%s: %s refuses %s %dx%d", label, camera,
                         image::pixel_format_name(c.format), c.width, c.height);
    }
    if (s.pixelFormat != want) {
      return Error::make(ErrorCode::kCaptureFormatRefused, "%s: asked for %s, %s offers %s", label,
                         image::pixel_format_name(c.format), camera,
                         s.pixelFormat.toString().c_str());
    }
    if ((static_cast<int32_t>(s.size.width) != c.width ||
         static_cast<int32_t>(s.size.height) != c.height) &&
        !c.accept_other_size) {
      return Error::make(ErrorCode::kCaptureFormatRefused,
                         "%s: asked for %dx%d, %s set %ux%u (accept_other_size uses it)", label,
                         c.width, c.height, camera, s.size.width, s.size.height);
    }
    if (int rc = camera_->configure(config_.get()); rc != 0) {
      return Error::make(ErrorCode::kCaptureFormatRefused, "%s: configure %s: %s", label, camera,
                         std::strerror(-rc));
    }
    format = {c.format, static_cast<int32_t>(s.size.width), static_cast<int32_t>(s.size.height),
              c.format == image::PixelFormat::kMjpeg ? 0 : static_cast<int32_t>(s.stride)};
    return Status();
  }

  Status allocate(const LibcameraConfig&, const char* label) {
    lc::Stream* stream = config_->at(0).stream();
    allocator_ = std::make_unique<lc::FrameBufferAllocator>(camera_);
    if (allocator_->allocate(stream) < 0) {
      return Error::make(ErrorCode::kCapture, "%s: allocating buffers on %s failed", label, camera);
    }
    const auto& fbs = allocator_->buffers(stream);
    if (fbs.size() < kMinBuffers || fbs.size() > kMaxCompletions) {
      return Error::make(ErrorCode::kCaptureFormatRefused, "%s: %s gave %zu buffers", label, camera,
                         fbs.size());
    }
    for (size_t i = 0; i < fbs.size(); ++i) {
      const lc::FrameBuffer::Plane& plane = fbs[i]->planes()[0];  // single-plane formats only
      void* p = ::mmap(nullptr, plane.length, PROT_READ, MAP_SHARED, plane.fd.get(), plane.offset);
      if (p == MAP_FAILED) {
        return Error::make(ErrorCode::kCapture, "%s: mmap of buffer %zu: %s", label, i,
                           std::strerror(errno));
      }
      maps_.emplace_back(p, plane.length);
      buffers.emplace_back(static_cast<const uint8_t*>(p), plane.length);
      std::unique_ptr<lc::Request> r = camera_->createRequest(i);
      if (!r || r->addBuffer(stream, fbs[i].get()) != 0) {
        return Error::make(ErrorCode::kCapture, "%s: building request %zu failed", label, i);
      }
      requests_.push_back(std::move(r));
    }
    return Status();
  }

  // libcamera's thread.
  void on_completed(lc::Request* r) {
    if (r->status() == lc::Request::RequestCancelled) return;
    const auto& buffers_of = r->buffers();
    if (buffers_of.empty()) return;
    const lc::FrameMetadata& m = buffers_of.begin()->second->metadata();
    LibcameraCompletion c;
    c.buffer = static_cast<uint32_t>(r->cookie());
    c.error = m.status == lc::FrameMetadata::FrameError;
    c.cancelled = m.status == lc::FrameMetadata::FrameCancelled;
    c.sequence = m.sequence;
    c.timestamp_ns = static_cast<int64_t>(m.timestamp);
    c.bytesused = m.planes().empty() ? 0 : m.planes()[0].bytesused;
    sink_->push(c);
  }

  void on_disconnected() {
    disconnected_.store(true);
    sink_->wake();
  }

  void close() {
    if (camera_) {
      if (started_) camera_->stop();
      camera_->requestCompleted.disconnect(this);
      camera_->disconnected.disconnect(this);
    }
    requests_.clear();
    for (auto& [p, n] : maps_) ::munmap(p, n);
    maps_.clear();
    buffers.clear();
    allocator_.reset();
    config_.reset();
    if (camera_ && acquired_) camera_->release();
    camera_.reset();
    manager_.reset();
  }

  std::shared_ptr<lc::CameraManager> manager_;
  std::shared_ptr<lc::Camera> camera_;
  std::unique_ptr<lc::CameraConfiguration> config_;
  std::unique_ptr<lc::FrameBufferAllocator> allocator_;
  std::vector<std::unique_ptr<lc::Request>> requests_;
  std::vector<std::pair<void*, size_t>> maps_;
  Completions* sink_ = nullptr;
  bool acquired_ = false, started_ = false;
  std::atomic<bool> disconnected_{false};
};

}  // namespace

Result<std::unique_ptr<CameraSession>> open_camera(const LibcameraConfig& config, const char* label,
                                                   Completions& sink) {
  auto s = std::make_unique<Session>();
  TLV_TRY(s->open(config, label, sink));
  return std::unique_ptr<CameraSession>(std::move(s));
}

}  // namespace internal

Result<std::vector<LibcameraCameraInfo>> list_libcamera_cameras() {
  Error err;
  auto manager = internal::shared_manager(err);
  if (!manager) return err;
  std::vector<LibcameraCameraInfo> out;
  for (const auto& cam : manager->cameras()) {
    LibcameraCameraInfo info;
    info.id = cam->id();
    if (auto model = cam->properties().get(libcamera::properties::Model)) info.model = *model;
    out.push_back(std::move(info));
  }
  return out;
}

std::string libcamera_version() { return libcamera::CameraManager::version(); }

}  // namespace tlvlink::capture
