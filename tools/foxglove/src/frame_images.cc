#include "tlvlink/foxglove/frame_images.h"

#include <map>
#include <memory>

#include "tlvlink/foxglove/mcap_recording.h"
#include "tlvlink/listen/client.h"

namespace tlvlink::foxglove {

Result<record::JpegFrameSource> stream_frame_images(const std::string& path, int32_t sensor) {
  TLV_ENSURE(sensor >= 0 && sensor <= 255, ErrorCode::kInvalidArgument,
             "record --stream: sensor %d is not a sensor index (0..255)", sensor);
  listen::ClientOptions options;
  options.reconnect = false;
  options.time_sync_ms = 0;
  std::shared_ptr<listen::Client> client;
  if (is_mcap_path(path)) {
    TLV_ASSIGN_OR_RETURN(std::unique_ptr<McapRecordSource> records, McapRecordSource::open(path));
    TLV_ASSIGN_OR_RETURN(
        client, listen::Client::open_replay(std::move(records), "replay:" + path, options));
  } else {
    TLV_ASSIGN_OR_RETURN(client, listen::Client::open("replay:" + path, options));
  }
  // Images of the other sensors, counted for the error when this one has none.
  auto others = std::make_shared<std::map<int32_t, int64_t>>();
  auto taken = std::make_shared<int64_t>(0);
  return record::JpegFrameSource([client, others, taken, path, sensor](
                                     std::vector<uint8_t>& jpeg,
                                     std::string& name) -> Result<bool> {
    for (;;) {
      TLV_ASSIGN_OR_RETURN(std::optional<listen::Message> m, client->next(1000));
      if (!m) {
        if (!client->ended()) continue;
        if (*taken > 0) return false;
        std::string seen;
        for (const auto& [s, n] : *others)
          seen +=
              (seen.empty() ? "" : ", ") + std::to_string(n) + " of sensor " + std::to_string(s);
        return Error::make(
            ErrorCode::kInvalidArgument,
            "record --stream: %s holds no frame image of sensor %d (%s)", path.c_str(), sensor,
            seen.empty() ? "none at all: the board ran with frame_images off, its default"
                         : ("it has " + seen).c_str());
      }
      auto f = m->frame_image();
      if (!f.ok()) continue;
      if (f.value().sensor != sensor) {
        ++(*others)[f.value().sensor];
        continue;
      }
      TLV_ENSURE(f.value().format == protocol::ImageFormat::kJpeg, ErrorCode::kFormat,
                 "record --stream: %s: image of frame %u is not a JPEG", path.c_str(),
                 f.value().frame_sequence);
      jpeg.assign(f.value().data.begin(), f.value().data.end());
      name = path + ": image of frame " + std::to_string(f.value().frame_sequence);
      ++*taken;
      return true;
    }
  });
}

}  // namespace tlvlink::foxglove
