// `tlvlink listen/replay --record X.mcap` and `tlvlink replay X.mcap` end to end: the MCAP
// recording of a run replays to exactly the lines the run printed (and the .tlvrec of the same
// run replays to), the recording file rules of .tlvrec hold for .mcap, bad files are named.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fixture_recording.h"
#include "listen/board_process.h"
#include "support/cli_run.h"
#include "support/temp_dir.h"
#include "tlvlink/capture/recording.h"
#include "tlvlink/foxglove/mcap_reader.h"
#include "tlvlink/foxglove/mcap_recording.h"

namespace tlvlink::testing {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The message lines of a --json run (the link_stats line differs between a live run and a replay).
std::vector<std::string> message_lines(const std::string& out) {
  std::vector<std::string> lines;
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("{\"type\":", 0) == 0 && line.rfind("{\"type\":\"link_stats\"", 0) != 0)
      lines.push_back(line);
  }
  return lines;
}

#define EXPECT_HAS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

TEST(FoxgloveCli, ReplayingTheMcapOfAReplayPrintsTheSameLines) {
  TempDir dir("fxcli");
  ASSERT_TRUE(listen::write_fixture_recording(dir / "f.tlvrec", false).ok());
  for (const char* mode : {"--json", ""}) {
    const std::string mcap = dir / (std::string("x") + mode + ".mcap");
    const CliRun original = run_tlvlink("replay " + dir / "f.tlvrec " + mode, Stderr::kDropped);
    ASSERT_RUN(original, 0);
    const CliRun recorded =
        run_tlvlink("replay " + dir / "f.tlvrec " + mode + " --record " + mcap, Stderr::kDropped);
    ASSERT_RUN(recorded, 0);
    EXPECT_EQ(recorded.out, original.out) << "recording does not change what is printed";
    const CliRun replayed = run_tlvlink("replay " + mcap + " " + mode, Stderr::kDropped);
    ASSERT_RUN(replayed, 0);
    EXPECT_EQ(replayed.out, original.out) << mode;
    EXPECT_GE(std::count(original.out.begin(), original.out.end(), '\n'), 13)
        << "the fixture's 13 messages";
  }
}

TEST(FoxgloveCli, ALiveMcapReplaysToTheLinesOfItsRun) {
  TempDir dir("fxcli");
  BoardProcess board("pty:" + dir / "tty", 200, 400, 2);
  const std::string mcap = dir / "live.mcap";
  const CliRun live = run_tlvlink(
      "listen --serial " + dir / "tty" + " --json --count 200 --record " + mcap, Stderr::kDropped);
  ASSERT_RUN(live, 0);
  const CliRun replay = run_tlvlink("replay " + mcap + " --json", Stderr::kDropped);
  ASSERT_RUN(replay, 0);
  const auto live_lines = message_lines(live.out), replay_lines = message_lines(replay.out);
  ASSERT_GE(live_lines.size(), 201u);  // a Hello and 200 predictions at least
  // The live session stopped after its 200th prediction; the replay decodes everything recorded
  // (bytes that arrived with the last ones): the first lines identical, clock included.
  ASSERT_GE(replay_lines.size(), live_lines.size());
  for (size_t i = 0; i < live_lines.size(); ++i)
    ASSERT_EQ(replay_lines[i], live_lines[i]) << "message " << i;
  // The JSON channels hold exactly the printed messages, each its line plus `timestamp`.
  auto file = foxglove::read_mcap_file(mcap);
  ASSERT_TRUE(file.ok()) << file.error().message();
  std::vector<std::string> json_messages;
  for (const auto& m : file->messages) {
    if (m.channel_id == foxglove::kRecordChannelId) continue;
    nlohmann::json j = nlohmann::json::parse(
        std::string(reinterpret_cast<const char*>(m.data.data()), m.data.size()));
    j.erase("timestamp");
    json_messages.push_back(j.dump());
  }
  ASSERT_EQ(json_messages.size(), live_lines.size());
  for (size_t i = 0; i < live_lines.size(); ++i) {
    EXPECT_EQ(json_messages[i], nlohmann::json::parse(live_lines[i]).dump()) << "message " << i;
  }
}

// Base64 of the listener's JSON lines, decoded (the test's own, RFC 4648 alphabet).
std::string from_base64(const std::string& text) {
  static const std::string kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  uint32_t bits = 0;
  int n = 0;
  for (char c : text) {
    const size_t v = kAlphabet.find(c);
    if (v == std::string::npos) continue;  // '=' padding
    bits = (bits << 6) | static_cast<uint32_t>(v);
    n += 6;
    if (n >= 8) out.push_back(static_cast<char>((bits >> (n -= 8)) & 0xFF));
  }
  return out;
}

// `record --stream`: a sensor's frame images in a stream recording (.tlvrec, and the .mcap of
// the same run) become a camera recording, each JPEG byte for byte, in order.
TEST(FoxgloveCli, RecordStreamTurnsASensorsFrameImagesIntoACameraRecording) {
  TempDir dir("fxcli");
  const std::string tlvrec = dir / "run.tlvrec", mcap = dir / "run.mcap";
  {
    // An image after every 2nd prediction: the odd ones, all of sensor 1 (fixture: sensor n % 2).
    BoardProcess board("pty:" + dir / "tty", 60, 400, 2, {"--images", "2", "--wait-host", "10"});
    const CliRun live =
        run_tlvlink("listen --serial " + dir / "tty" + " --json --count 60 --record " + tlvrec,
                    Stderr::kDropped);
    ASSERT_RUN(live, 0);
  }
  ASSERT_RUN(run_tlvlink("replay " + tlvrec + " --record " + mcap, Stderr::kDropped), 0);
  const CliRun lines = run_tlvlink("replay " + tlvrec + " --json", Stderr::kDropped);
  ASSERT_RUN(lines, 0);
  std::vector<std::string> jpegs;
  for (const std::string& line : message_lines(lines.out)) {
    const nlohmann::json j = nlohmann::json::parse(line);
    if (j["type"] == "frame_image" && j["sensor"] == 1)
      jpegs.push_back(from_base64(j["data"].get<std::string>()));
  }
  ASSERT_GE(jpegs.size(), 20u) << lines.out;
  for (const std::string& source : {tlvrec, mcap}) {
    SCOPED_TRACE(source);
    const std::string cam = dir / "cam.tlvraw";
    const CliRun r =
        run_tlvlink("record --stream " + source + " --sensor 1 --fps 15 --overwrite -o " + cam);
    ASSERT_RUN(r, 0);
    EXPECT_HAS(r.out, std::to_string(jpegs.size()) + " images as " + std::to_string(jpegs.size()) +
                          " frames");
    auto reader = capture::RecordingReader::open(cam);
    ASSERT_TRUE(reader.ok()) << reader.error().message();
    capture::RecordInfo info;
    size_t i = 0;
    for (uint64_t at = reader->first_record();; at = info.next, ++i) {
      auto more = reader->record_at(at, info);
      ASSERT_TRUE(more.ok()) << more.error().message();
      if (!*more) break;
      ASSERT_LT(i, jpegs.size());
      std::string bytes(info.bytes, '\0');
      ASSERT_TRUE(
          reader
              ->read_frame(
                  info, std::span<uint8_t>(reinterpret_cast<uint8_t*>(bytes.data()), bytes.size()),
                  true)
              .ok());
      EXPECT_EQ(bytes, jpegs[i]) << "image " << i;
    }
    EXPECT_EQ(i, jpegs.size());
  }
  // A sensor without images is named with what the recording has; a replay of it refused.
  const CliRun none =
      run_tlvlink("record --stream " + mcap + " --sensor 0 -o " + dir / "none.tlvraw");
  EXPECT_RUN(none, 2);  // the sensor asked for is not in this recording
  EXPECT_HAS(none.out, "holds no frame image of sensor 0 (it has " + std::to_string(jpegs.size()) +
                           " of sensor 1)");
  EXPECT_FALSE(std::filesystem::exists(dir / "none.tlvraw"));
  const CliRun both =
      run_tlvlink("record --stream " + mcap + " --images " + dir / "." + " -o " + dir / "x.tlvraw");
  EXPECT_RUN(both, 2);
}

TEST(FoxgloveCli, TheRecordingFileRulesHoldForMcap) {
  TempDir dir("fxcli");
  ASSERT_TRUE(listen::write_fixture_recording(dir / "f.tlvrec", false).ok());
  const std::string old = dir / "old.mcap";
  { std::ofstream(old) << "yesterday"; }
  const CliRun refused = run_tlvlink("replay " + dir / "f.tlvrec --record " + old);
  EXPECT_RUN(refused, 2);
  EXPECT_HAS(refused.out, old + " already exists (give --overwrite");
  EXPECT_EQ(slurp(old), "yesterday");
  EXPECT_RUN(
      run_tlvlink("replay " + dir / "f.tlvrec --overwrite --record " + old, Stderr::kDropped), 0);
  EXPECT_EQ(slurp(old).substr(1, 4), "MCAP");
  const std::string fifo = dir / "fifo.mcap";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const CliRun to_fifo =
      run_cli("timeout -k 5 30 " TLVLINK_CLI_BINARY, "replay " + dir / "f.tlvrec --record " + fifo);
  EXPECT_RUN(to_fifo, 1);
  EXPECT_HAS(to_fifo.out, fifo + ": not a regular file (FIFO)");
  const CliRun from_fifo = run_cli("timeout -k 5 30 " TLVLINK_CLI_BINARY, "replay " + fifo);
  EXPECT_RUN(from_fifo, 1);
  EXPECT_HAS(from_fifo.out, "not a regular file (FIFO)");
  // A replay cannot write a .tlvrec (copy the file instead), only an MCAP.
  const CliRun tlvrec = run_tlvlink("replay " + dir / "f.tlvrec --record " + dir / "copy.tlvrec");
  EXPECT_RUN(tlvrec, 2);
  EXPECT_HAS(tlvrec.out, "copy the file instead");
}

// A file-size limit during a live session: the session stops with the path and the reason, exit 1.
TEST(FoxgloveCli, AFailedMcapWriteEndsTheSession) {
  TempDir dir("fxcli");
  BoardProcess board("pty:" + dir / "tty", 20000, 2000, 3);
  const std::string mcap = dir / "limited.mcap";
  const CliRun limited =
      run_cli("timeout 30 bash",
              "-c 'ulimit -f 64; exec \"$0\" \"$@\"' " TLVLINK_CLI_BINARY " listen --serial " +
                  dir / "tty" + " --count 20000 --duration 20 --record " + mcap,
              Stderr::kMerged);
  EXPECT_RUN(limited, 1);
  EXPECT_HAS(limited.out.substr(limited.out.size() > 3000 ? limited.out.size() - 3000 : 0),
             "writing MCAP recording " + mcap + ": file size limit reached");
  EXPECT_LE(std::filesystem::file_size(mcap), 65536u);
}

TEST(FoxgloveCli, BadMcapFilesAreNamed) {
  TempDir dir("fxcli");
  const std::string junk = dir / "junk.mcap";
  { std::ofstream(junk) << "not an mcap file at all"; }
  const CliRun r = run_tlvlink("replay " + junk);
  EXPECT_RUN(r, 1);
  EXPECT_HAS(r.out, junk + " is not an MCAP file (no MCAP magic at offset 0)");
  // An MCAP file without the record channel (not a tlvlink recording).
  const std::string other = dir / "other.mcap";
  {
    auto w = foxglove::McapWriter::create(other, false).value();
    ASSERT_TRUE(w->close().ok());
  }
  const CliRun o = run_tlvlink("replay " + other);
  EXPECT_RUN(o, 1);
  EXPECT_HAS(o.out, "has no /tlvlink/records channel");
}

}  // namespace
}  // namespace tlvlink::testing
