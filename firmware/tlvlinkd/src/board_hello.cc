#include "board_hello.h"

#include <unistd.h>

#include <vector>

#include "tlvlink/image/pixel_format.h"

namespace tlvlink::daemon::internal {
namespace {

#ifndef TLVLINK_BOARD_NAME
#define TLVLINK_BOARD_NAME "unknown"
#endif
#ifndef TLVLINK_VERSION
#define TLVLINK_VERSION "0"
#endif

}  // namespace

std::unique_ptr<stream::HelloBuilder> make_hello(const DaemonConfig& config, const Model& model,
                                                 const stream::OutputNames& names) {
  char host[256] = "board";
  gethostname(host, sizeof host - 1);
  const stream::BoardIdentity board{host, TLVLINK_BOARD_NAME, TLVLINK_VERSION,
                                    static_cast<uint64_t>(getpid())};
  std::vector<stream::SensorDescription> sensors;
  for (const SensorConfig& s : config.sensors) {
    sensors.push_back({s.name, s.sensor_model, image::pixel_format_name(s.format.format),
                       s.format.width, s.format.height, s.fps});
  }
  return std::make_unique<stream::HelloBuilder>(board, model, config.model, sensors, names);
}

stream::StreamTotals stream_totals(const RunTotals& r) {
  stream::StreamTotals t;
  t.seconds = r.seconds;
  t.sensors = r.sensors;
  t.sensor_fps = r.sensor_fps;
  t.sensor_frames = r.sensor_frames;
  t.sensor_encoded = r.sensor_encoded;
  t.sensor_gated = r.sensor_gated;
  t.capture_gap = r.drops_sequence;
  t.capture_error = r.bad_frames + r.decode_errors;
  // Camera frames skipped for a newer one (the capture thread busy) and decoded frames dropped
  // (inference behind) are both inference_busy; the stream's "stale" is the Sender's (messages
  // too old to send), and its queue_full is added to this output queue's (one entry a cause).
  t.inference_busy = r.drops_stale + r.drops_queue;
  t.queue_full = r.drops_output;
  t.frame_images = r.frame_images;
  t.image_busy = r.drops_image;
  t.cpu_percent = r.process_cpu_pct;
  t.cpu_cores = static_cast<uint8_t>(sysconf(_SC_NPROCESSORS_ONLN));
  t.rss_bytes = static_cast<uint64_t>(r.peak_rss_kb) * 1024;
  return t;
}

}  // namespace tlvlink::daemon::internal
