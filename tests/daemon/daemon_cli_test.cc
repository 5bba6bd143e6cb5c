// tlvlinkd end to end on its own outputs and paths (issue 31): an output that cannot write is
// counted, named with its reason in the summary and makes the exit code 1; a reader that closes
// the pipe ends the run with its summary (no SIGPIPE death); a pty link over somebody's file and
// FIFOs where files are expected are refused by --check and at start, without hanging (every run
// under `timeout -k 5 30`: exit 124 = it hung; -k because a daemon stuck before its signal loop
// has SIGTERM blocked); a recording with no good frame stops the loop.
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/cli_run.h"
#include "support/temp_dir.h"
#include "tlvlink/capture/recording.h"

namespace tlvlink::daemon {
namespace {

namespace fs = std::filesystem;
using testing::CliRun;
using testing::run_cli;

constexpr const char* kModel = TLVLINK_SOURCE_DIR "/firmware/models/touch-tiny-int8.tlvm";
constexpr int kW = 320, kH = 240, kFrames = 40;  // a DIGIT's YUYV stream

CliRun tlvlinkd(const std::string& args) {
  return run_cli("timeout -k 5 30 " TLVLINKD_BINARY, args);
}

bool contains(const CliRun& r, const std::string& text) {
  return r.out.find(text) != std::string::npos;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

constexpr int kLongFrames = 1200;

// `total` frames at 60 fps: kFrames distinct ones, then repeats of them (the file stays small);
// with `damaged`, every stored frame's bytes fail their checksum.
void write_recording(const std::string& path, bool damaged, int total = kFrames) {
  capture::RecordingFormat f;
  f.format = {image::PixelFormat::kYuyv, kW, kH, kW * 2};
  f.fps_numerator = 60;
  auto w = capture::RecordingWriter::create(path, f);
  ASSERT_TRUE(w.ok()) << w.error().message();
  std::vector<capture::RecordedBytes> stored;
  std::vector<uint8_t> frame(static_cast<size_t>(kW * kH * 2));
  for (int k = 0; k < total; ++k) {
    const int64_t t = 1'000'000'000 + k * 16'666'667LL;
    if (k >= kFrames) {
      ASSERT_TRUE(
          w->append_repeat(stored[static_cast<size_t>(k % kFrames)], t, static_cast<uint32_t>(k))
              .ok());
      continue;
    }
    for (size_t i = 0; i < frame.size(); ++i) frame[i] = static_cast<uint8_t>((i * 7 + k) & 0xFF);
    auto r = w->append(frame, t, static_cast<uint32_t>(k));
    ASSERT_TRUE(r.ok()) << r.error().message();
    stored.push_back(*r);
  }
  ASSERT_TRUE(w->close().ok());
  if (!damaged) return;
  std::fstream io(path, std::ios::in | std::ios::out | std::ios::binary);
  for (const capture::RecordedBytes& b : stored) {
    io.seekp(static_cast<std::streamoff>(b.offset + 3));
    io.put('\xEE');
  }
}

// Starts tlvlinkd on config `c` (stderr into `err`), sends SIGTERM two seconds in, and expects
// exit 0 within a second of it.
void expect_sigterm_stops_within_a_second(const std::string& c, const std::string& err) {
  CliRun r = run_cli("timeout 60 bash",
                     std::string("-c '\"$0\" --config \"$1\" 2>\"$2\" & pid=$!; sleep 2; "
                                 "t0=$(date +%s%N); kill -TERM $pid; wait $pid; rc=$?; "
                                 "echo stop_ms=$(( ($(date +%s%N) - t0) / 1000000 )) rc=$rc' ") +
                         TLVLINKD_BINARY + " " + c + " " + err);
  EXPECT_TRUE(contains(r, " rc=0")) << r.out << slurp(err);
  const size_t at = r.out.find("stop_ms=");
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_LT(std::stoi(r.out.substr(at + 8)), 1000) << r.out;
}

class DaemonCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("daemon_cli");
    write_recording(path("good.tlvraw"), false);
    write_recording(path("bad.tlvraw"), true);
    write_recording(path("long.tlvraw"), false, kLongFrames);
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string path(const std::string& rel) { return (*dir_) / rel; }

  // A configuration replaying `recording` as fast as it is read, into `output`.
  static std::string config(const std::string& name, const std::string& output,
                            const std::string& recording, const std::string& top = "",
                            bool loop = false) {
    const std::string p = path(name + ".toml");
    std::ofstream(p) << "model = \"" << kModel << "\"\nverify_model = false\noutput = " << output
                     << "\n"
                     << top << "\n[[sensor]]\nname = \"a\"\nmodel = \"digit\"\n"
                     << "source = \"replay\"\ndevice = \"" << recording << "\"\nrealtime = false\n"
                     << "loop = " << (loop ? "true" : "false") << "\n";
    return p;
  }
  static std::string fifo() {
    const std::string p = path("fifo");
    if (!fs::exists(p)) {
      EXPECT_EQ(::mkfifo(p.c_str(), 0600), 0);
    }
    return p;
  }

  static testing::TempDir* dir_;
};
testing::TempDir* DaemonCli::dir_ = nullptr;

// Item 1: a config pointing `pty:` at notes.txt: --check and start refuse, the file is untouched.
TEST_F(DaemonCli, PtyOutputOverARegularFileIsRefusedAndTheFileKept) {
  const std::string notes = path("notes.txt");
  std::ofstream(notes) << "my notes\n";
  const std::string c = config("pty_notes", "\"pty:" + notes + "\"", path("good.tlvraw"));
  CliRun r = tlvlinkd("--config " + c + " --check");
  EXPECT_RUN(r, 2);
  EXPECT_TRUE(contains(r, notes + " already exists and is not a symlink")) << r.out;
  r = tlvlinkd("--config " + c);
  EXPECT_RUN(r, 2);
  struct stat st {};
  ASSERT_EQ(::lstat(notes.c_str(), &st), 0);
  EXPECT_TRUE(S_ISREG(st.st_mode));
  EXPECT_EQ(slurp(notes), "my notes\n");
}

// Item 2: every record lost to a full device is counted, the summary names the output and the
// reason, and the exit code is 1.
TEST_F(DaemonCli, JsonlOutputThatCannotWriteIsNamedAndExitOne) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  CliRun r = tlvlinkd("--config " + config("full", "\"jsonl:/dev/full\"", path("good.tlvraw")));
  EXPECT_RUN(r, 1);
  EXPECT_TRUE(contains(r, "output jsonl:/dev/full: ")) << r.out;
  EXPECT_TRUE(contains(r, "record(s) not written (")) << r.out;
  EXPECT_TRUE(contains(r, ": disk full)")) << r.out;
  // One count everywhere: the drops line, the output's line and the last line agree.
  const size_t at = r.out.find("output jsonl:/dev/full: ");
  ASSERT_NE(at, std::string::npos);
  const std::string lost = r.out.substr(at + 24, r.out.find(' ', at + 24) - at - 24);
  EXPECT_TRUE(contains(r, "write errors " + lost + ";")) << r.out;
  EXPECT_TRUE(contains(r, "tlvlinkd: " + lost + " record(s) not written to an output")) << r.out;
}

// Item 7: `jsonl:-` into `head -n 3`: no death by SIGPIPE; the run ends (the replay loops forever
// otherwise) with its summary, exit 0 (nothing was lost: the reader left).
TEST_F(DaemonCli, AClosedPipeEndsTheRunWithItsSummary) {
  const std::string c = config("pipe", "\"jsonl:-\"", path("good.tlvraw"), "", true);
  const std::string err = path("pipe.err");
  CliRun r =
      run_cli("timeout 60 bash", std::string("-c '\"$0\" --config \"$1\" 2>\"$2\" | head -n 3 "
                                             ">/dev/null; echo daemon_rc=${PIPESTATUS[0]}' ") +
                                     TLVLINKD_BINARY + " " + c + " " + err);
  EXPECT_TRUE(contains(r, "daemon_rc=0")) << r.out << slurp(err);
  const std::string log = slurp(err);
  EXPECT_NE(log.find("output jsonl:-: closed by its reader"), std::string::npos) << log;
  EXPECT_NE(log.find("drops: stale"), std::string::npos) << "no summary: " << log;
}

// Item 5: a FIFO as the replay recording, the JSON-lines file or the public key: refused by
// --check and at start (exit 2) at once, naming the path.
TEST_F(DaemonCli, FifosAreRefusedByCheckAndAtStartWithoutHanging) {
  const std::string f = fifo();
  const std::vector<std::string> configs = {
      config("fifo_replay", "\"jsonl:" + path("o.jsonl") + "\"", f),
      config("fifo_jsonl", "\"jsonl:" + f + "\"", path("good.tlvraw")),
      config("fifo_key", "\"jsonl:" + path("o.jsonl") + "\"", path("good.tlvraw"),
             "model_public_key = \"" + f + "\"")};
  for (const std::string& c : configs) {
    for (const std::string extra : {" --check", ""}) {
      const auto t0 = std::chrono::steady_clock::now();
      CliRun r = tlvlinkd("--config " + c + extra);
      EXPECT_RUN(r, 2) << c << extra;
      EXPECT_TRUE(contains(r, f + ": not a regular file") ||
                  contains(r, "jsonl:" + f + ": not a regular file"))
          << c << extra << ": " << r.out;
      EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(10));
    }
  }
}

// Item 6: loop = true, realtime = false, every frame failing its checksum: the replay stops
// with an error naming the recording (it spun at ~92 % of a core, deaf to SIGTERM).
TEST_F(DaemonCli, LoopOverARecordingWithNoGoodFrameStopsWithAnError) {
  const auto t0 = std::chrono::steady_clock::now();
  CliRun r = tlvlinkd("--config " + config("all_bad", "\"jsonl:" + path("bad.jsonl") + "\"",
                                           path("bad.tlvraw"), "", true));
  EXPECT_RUN(r, 1);
  EXPECT_TRUE(contains(r, "no good frame in a whole pass of " + path("bad.tlvraw"))) << r.out;
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(15));
}

// Item 5: SIGTERM stops a running daemon (a looping replay at the camera's pace) within a
// second, exit 0, summary printed.
TEST_F(DaemonCli, SigtermStopsTheRunWithinASecond) {
  const std::string c =
      config("sigterm", "\"jsonl:" + path("sigterm.jsonl") + "\"", path("good.tlvraw"), "", true);
  // realtime = true (the camera's pace): the replay never ends on its own.
  std::string text = slurp(c);
  text.replace(text.find("realtime = false"), 16, "realtime = true");
  std::ofstream(c) << text;
  const std::string err = path("sigterm.err");
  expect_sigterm_stops_within_a_second(c, err);
  EXPECT_NE(slurp(err).find("drops: stale"), std::string::npos) << "no summary: " << slurp(err);
}

// A replay read at speed (realtime = false) waits for the daemon instead of dropping: with one
// waiting frame per sensor and one waiting record, every frame of the recording is processed and
// written, once each, in order. (With the camera's drop-oldest policy this run loses frames at
// both queues.)
TEST_F(DaemonCli, AReplayReadAtSpeedProcessesAndWritesEveryFrame) {
  const std::string out = path("every.jsonl");
  CliRun r = tlvlinkd("--config " + config("every", "\"jsonl:" + out + "\"", path("long.tlvraw"),
                                           "queue_frames = 1\noutput_queue = 1\nembedding = true"));
  EXPECT_RUN(r, 0);
  EXPECT_TRUE(contains(r, "queue 0, output 0, write errors 0")) << r.out;
  std::ifstream in(out);
  std::string line;
  int64_t expected = -1;  // the first frame's sequence, then each next one
  int frames = 0;
  while (std::getline(in, line)) {
    const size_t at = line.find("\"frame_sequence\":");
    if (at == std::string::npos) continue;
    const int64_t seq = std::stoll(line.substr(at + 17));
    if (expected >= 0) {
      EXPECT_EQ(seq, expected) << "frame " << frames;
    }
    expected = seq + 1;
    ++frames;
  }
  // The replay may skip the sensor model's warm-up frames at the start, nothing after them.
  EXPECT_GE(frames, kLongFrames - 10);
  EXPECT_EQ(expected, kLongFrames) << "the last frame was not written";
}

// Stopping while a replay read at speed waits for the consumer: SIGTERM still ends it at once.
TEST_F(DaemonCli, SigtermStopsAReplayReadAtSpeed) {
  const std::string c = config("sigterm_speed", "\"jsonl:/dev/null\"", path("long.tlvraw"),
                               "queue_frames = 1\noutput_queue = 1", true);
  const std::string err = path("sigterm_speed.err");
  expect_sigterm_stops_within_a_second(c, err);
  EXPECT_NE(slurp(err).find("queue 0, output 0"), std::string::npos) << slurp(err);
}

// Item 10: --check runs what start runs (the unit cases are in config_test.cc): one through the
// binary, so main's --check path is covered too.
TEST_F(DaemonCli, CheckRefusesABadLinkAsStartDoes) {
  const std::string c = config("baud", "\"serial:/dev/null,baud=-5\"", path("good.tlvraw"));
  CliRun r = tlvlinkd("--config " + c + " --check");
  EXPECT_RUN(r, 2);
  EXPECT_TRUE(contains(r, "-5 baud is not a standard rate")) << r.out;
}

}  // namespace
}  // namespace tlvlink::daemon
