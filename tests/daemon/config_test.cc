// tlvlinkd's configuration: a full file parses into what it says; every kind of mistake is an
// error naming the file, line and key.
#include <string>

#include <gtest/gtest.h>

#include "tlvlink/daemon/config.h"

namespace tlvlink::daemon {
namespace {

constexpr const char* kGood = R"(model = "m.tlvm"
executor = "reference"
threads = 2
heads = ["material", "hard_soft"]
smoothing_ms = 200
embedding = true
output = "jsonl:/tmp/out.jsonl"
control = "stdin"

[contact]
enabled = true
reference_frames = 30
noise_multiple = 6.5

[grasp]
mode = "commanded"
settle_ms = 0
after_delay_ms = 250

[[sensor]]
name = "left"
model = "gelsight-mini"
finger = "A"
device = "usb:0c45:636d:2BDF-Q7KX"
controls = "exposure_time_absolute=180, white_balance_temperature=4500"

[[sensor]]
name = "right"
model = "digit"
finger = "B"
source = "v4l2"
device = "/dev/video2"
fps = 30
)";

std::string error_of(const std::string& text) {
  auto c = parse_config(text, "t.toml");
  return c.ok() ? "" : c.error().message();
}

TEST(DaemonConfig, AFullFileParses) {
  auto c = parse_config(kGood, "t.toml");
  ASSERT_TRUE(c.ok()) << c.error().message();
  EXPECT_EQ(c->model, "m.tlvm");
  EXPECT_EQ(c->executor, "reference");
  EXPECT_EQ(c->threads, 2);
  EXPECT_EQ(c->processing.heads, (std::vector<std::string>{"material", "hard_soft"}));
  EXPECT_EQ(c->processing.smoothing_tau_ns, 200'000'000);
  EXPECT_TRUE(c->processing.report_embedding);
  EXPECT_EQ(c->control, ControlInput::kStdin);
  EXPECT_EQ(c->processing.contact.reference_frames, 30);
  EXPECT_FLOAT_EQ(c->processing.contact.noise_multiple, 6.5f);
  EXPECT_EQ(c->processing.grasp_options.mode, pipeline::GraspOptions::Mode::kCommanded);
  EXPECT_EQ(c->processing.grasp_options.after_delay_ns, 250'000'000);
  ASSERT_EQ(c->sensors.size(), 2u);
  const SensorConfig& l = c->sensors[0];
  EXPECT_EQ(l.format.format, image::PixelFormat::kMjpeg);  // the Mini's only mode
  EXPECT_EQ(l.format.width, 3280);
  EXPECT_DOUBLE_EQ(l.view.crop, 0.15);
  EXPECT_EQ(l.warmup_frames, 5u);
  EXPECT_EQ(l.controls.size(), 2u);
  EXPECT_EQ(l.finger, 0);
  const SensorConfig& r = c->sensors[1];
  EXPECT_EQ(r.format.format, image::PixelFormat::kYuyv);
  EXPECT_EQ(r.view.orientation, image::Orientation::kTransposed);
  EXPECT_DOUBLE_EQ(r.fps, 30);
  // Frames already upright (a DIGIT's processed frames, as recorded by `sim scenario --offline`).
  std::string upright = kGood;
  upright.replace(upright.find("fps = 30"), 8, "fps = 30\norientation = \"upright\"");
  auto u = parse_config(upright, "t.toml");
  ASSERT_TRUE(u.ok()) << u.error().message();
  EXPECT_EQ(u->sensors[1].view.orientation, image::Orientation::kUpright);
  upright.replace(upright.find("\"upright\""), 9, "\"sideways\"");
  EXPECT_NE(error_of(upright).find("orientation: 'sideways' is not one of upright, transposed"),
            std::string::npos)
      << error_of(upright);
}

TEST(DaemonConfig, MistakesNameFileLineAndKey) {
  const std::string t = kGood;
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string out = t;
    out.replace(out.find(from), from.size(), to);
    return out;
  };
  EXPECT_NE(error_of(std::string(kGood) + "colour = 1\n").find("sensor[1].colour: unknown key"),
            std::string::npos)
      << error_of(std::string(kGood) + "colour = 1\n");
  EXPECT_EQ(error_of(with("threads = 2", "threads = \"two\"")),
            "t.toml:3: threads: expected an integer, got a string");
  EXPECT_NE(error_of("speed = 3\n" + t).find("t.toml:1: speed: unknown key"), std::string::npos);
  EXPECT_EQ(error_of(with("threads = 2", "threads = 0")), "t.toml:3: threads: 0 outside [1, 64]");
  std::string no_model = t.substr(t.find('\n') + 1);
  EXPECT_NE(error_of(no_model).find("model: required"), std::string::npos);
  std::string bad_sensor = t;
  bad_sensor.replace(bad_sensor.find("model = \"digit\""), 15, "model = \"gelsite\"");
  EXPECT_NE(error_of(bad_sensor).find("sensor model 'gelsite' unknown (known: gelsight-mini"),
            std::string::npos);
  std::string two_a = t;
  two_a.replace(two_a.find("finger = \"B\""), 12, "finger = \"A\"");
  EXPECT_NE(error_of(two_a).find("sensors 'left' and 'right' are both finger A"),
            std::string::npos);
  std::string bad_mode = t;
  bad_mode.replace(bad_mode.find("\"commanded\""), 11, "\"sometimes\"");
  EXPECT_NE(
      error_of(bad_mode).find("grasp.mode: 'sometimes' is not one of detected, commanded, off"),
      std::string::npos);
  EXPECT_NE(error_of("model = \"m\"\n").find("at least one [[sensor]]"), std::string::npos);
  EXPECT_NE(error_of("model = \n").find("t.toml:1:"), std::string::npos);  // TOML syntax
  std::string bad_device = t;
  bad_device.replace(bad_device.find("usb:0c45:636d:2BDF-Q7KX"), 23, "usb:zz:636d");
  EXPECT_NE(error_of(bad_device).find("sensor[0].device"), std::string::npos)
      << error_of(bad_device);
}

// Issue 31 item 10: what start refuses, the configuration (and so --check) refuses, naming the key.
TEST(DaemonConfig, RefusesWhatStartWouldRefuse) {
  const std::string t = kGood;
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string out = t;
    out.replace(out.find(from), from.size(), to);
    return out;
  };
  EXPECT_NE(
      error_of(with("fps = 30", "fps = 30\njpeg_scale = 3")).find("sensor[1].jpeg_scale: 3 is not"),
      std::string::npos)
      << error_of(with("fps = 30", "fps = 30\njpeg_scale = 3"));
  EXPECT_EQ(error_of(with("fps = 30", "fps = 30\njpeg_scale = 4")), "");
  const std::string nine = with("heads = [\"material\", \"hard_soft\"]",
                                "heads = [\"a\",\"b\",\"c\",\"d\",\"e\",\"f\",\"g\",\"h\",\"i\"]");
  EXPECT_NE(error_of(nine).find("heads: 9 heads; at most 8"), std::string::npos) << error_of(nine);
  const std::string baud =
      with("output = \"jsonl:/tmp/out.jsonl\"", "output = \"serial:/dev/null,baud=-5\"");
  EXPECT_NE(error_of(baud).find("output: serial link /dev/null: -5 baud is not a standard rate"),
            std::string::npos)
      << error_of(baud);
  const std::string name = with("name = \"left\"", "name = \"" + std::string(20000, 'x') + "\"");
  EXPECT_NE(error_of(name).find("sensor[0].name: 20000 bytes; at most 64"), std::string::npos);
#if defined(TLVLINK_HAVE_STREAM_LINK)
  // FrameImages (issue 33): on the stream link only; a rate, a quality and a size that fit.
  const std::string images = with("output = \"jsonl:/tmp/out.jsonl\"",
                                  "output = \"serial:/dev/null\"\nframe_images = \"view\"");
  EXPECT_EQ(error_of(images), "");
  EXPECT_NE(error_of(with("output = \"jsonl:/tmp/out.jsonl\"", "frame_images = \"input\""))
                .find("frame_images: images go on the stream link"),
            std::string::npos);
  const auto images_with = [&](const std::string& extra) {
    std::string out = images;
    out.replace(out.find("frame_images = \"view\""), 21, "frame_images = \"view\"\n" + extra);
    return error_of(out);
  };
  EXPECT_NE(images_with("frame_images_per_second = 16")
                .find("frame_images_per_second: 16 outside [1, 15]"),
            std::string::npos);
  EXPECT_NE(images_with("frame_images = 1").find("frame_images"), std::string::npos);
  const std::string big = images_with("frame_image_max_side = 1024\nframe_image_quality = 95");
  EXPECT_NE(big.find("frame_image_max_side: a "), std::string::npos) << big;
  EXPECT_NE(big.find("a FrameImage carries"), std::string::npos) << big;
  EXPECT_EQ(images_with("frame_image_max_side = 200\nframe_image_quality = 90"), "");
#endif
#if !defined(TLVLINK_HAVE_LIBCAMERA)
  const std::string libcamera = with("source = \"v4l2\"", "source = \"libcamera\"");
  EXPECT_NE(error_of(libcamera).find("sensor[1].source: this tlvlinkd was built without libcamera"),
            std::string::npos)
      << error_of(libcamera);
#endif
}

TEST(DaemonConfig, FilesMustBeRegular) {
  EXPECT_NE(std::string(load_config("/dev/zero").error().message()).find("not a regular file"),
            std::string::npos);
  EXPECT_EQ(load_config("/nonexistent/x.toml").error().code(), ErrorCode::kIo);
}

}  // namespace
}  // namespace tlvlink::daemon
