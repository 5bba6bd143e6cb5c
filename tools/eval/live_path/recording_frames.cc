// recording_frames: decodes chosen frames of a .tlvraw recording with the daemon's FrameDecoder
// (the gelsight-mini SensorView of capture::find_sensor_model) and writes OUTDIR/SSSS_r.ppm.
// Usage: recording_frames REC OUTDIR SEQ...
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>
#include "tlvlink/capture/recording.h"
#include "tlvlink/capture/sensor_models.h"
#include "tlvlink/image/frame_decoder.h"
using namespace tlvlink;
int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: recording_frames REC OUTDIR SEQ...\n");
    return 2;
  }
  auto rec = capture::RecordingReader::open(argv[1]).value();
  std::string out = argv[2];
  std::set<uint32_t> want;
  for (int i = 3; i < argc; ++i) want.insert(static_cast<uint32_t>(std::atoi(argv[i])));
  const capture::SensorModel* sm = capture::find_sensor_model("gelsight-mini");
  auto dec = image::FrameDecoder::create(rec.summary().format.format, sm->view).value();
  std::vector<uint8_t> bytes(40 << 20), rgb(dec.output_bytes());
  uint64_t off = rec.first_record();
  capture::RecordInfo info;
  while (rec.record_at(off, info).value()) {
    if (want.count(info.sequence)) {
      if (!rec.read_frame(info, bytes, false).ok()) return 1;
      auto st = dec.decode({bytes.data(), info.bytes}, rgb, "frame");
      if (!st.ok()) {
        std::fprintf(stderr, "%s\n", st.error().message());
        return 1;
      }
      char name[512];
      std::snprintf(name, sizeof name, "%s/%04u_r.ppm", out.c_str(), info.sequence);
      FILE* f = std::fopen(name, "wb");
      std::fprintf(f, "P6\n%d %d\n255\n", sm->view.width, sm->view.height);
      std::fwrite(rgb.data(), 1, rgb.size(), f);
      std::fclose(f);
      if (info.sequence == *want.begin()) {
        std::snprintf(name, sizeof name, "%s/%04u_raw.jpg", out.c_str(), info.sequence);
        f = std::fopen(name, "wb");
        std::fwrite(bytes.data(), 1, info.bytes, f);
        std::fclose(f);
      }
    }
    off = info.next;
  }
  return 0;
}
