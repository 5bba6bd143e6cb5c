// `tlvlink listen` and `tlvlink replay` end to end, against a board process
// (tlvlink_stream_check board) on a pty: JSON lines, a live session and the replay of its
// recording print the same lines, commands and exit codes, an absent device, bad input.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fixture_recording.h"
#include "listen/board_process.h"
#include "support/cli_run.h"
#include "support/temp_dir.h"

extern char** environ;

namespace tlvlink::testing {
namespace {

std::vector<nlohmann::json> json_lines(const std::string& out, bool messages_only = true) {
  std::vector<nlohmann::json> lines;
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] != '{') continue;
    nlohmann::json j = nlohmann::json::parse(line);
    if (messages_only && j["type"] == "link_stats") continue;
    lines.push_back(std::move(j));
  }
  return lines;
}

TEST(CliListen, LiveJsonAndItsRecordingReplayTheSame) {
  TempDir dir("listen");
  BoardProcess board("pty:" + dir / "tty", 200, 400, 2);
  const CliRun live =
      run_tlvlink("listen --serial " + dir / "tty" + " --json --count 200 --record " + dir / "rec",
                  Stderr::kDropped);
  ASSERT_RUN(live, 0);
  const auto live_lines = json_lines(live.out);
  size_t predictions = 0;
  for (const auto& j : live_lines) predictions += j["type"] == "frame_prediction";
  EXPECT_EQ(predictions, 200u);
  EXPECT_EQ(live_lines.front()["type"], "hello");
  EXPECT_EQ(live_lines.front()["schema_matches"], true);
  const CliRun replay = run_tlvlink("replay " + dir / "rec" + " --json", Stderr::kDropped);
  ASSERT_RUN(replay, 0);
  const auto replay_lines = json_lines(replay.out);
  // The live session stopped after its 200th prediction; the replay sees everything recorded:
  // at least as many messages, and the first ones identical, timestamps and clock included.
  ASSERT_GE(replay_lines.size(), live_lines.size());
  for (size_t i = 0; i < live_lines.size(); ++i)
    ASSERT_EQ(replay_lines[i], live_lines[i]) << "message " << i;
  const auto stats = json_lines(replay.out, false).back();
  ASSERT_EQ(stats["type"], "link_stats");
  EXPECT_EQ(stats["stats"]["rejected"]["crc"], 0);
}

TEST(CliListen, TextLinesNameHeadsAndLabels) {
  TempDir dir("listen");
  BoardProcess board("pty:" + dir / "tty", 20, 200, 1);
  const CliRun live = run_tlvlink("listen --serial " + dir / "tty" + " --count 20");
  ASSERT_RUN(live, 0);
  EXPECT_NE(live.out.find("hello  test-board (host-x86_64, firmware 0.1.0-test)"),
            std::string::npos)
      << live.out;
  EXPECT_NE(live.out.find("material="), std::string::npos) << live.out;
  EXPECT_NE(live.out.find("hardness="), std::string::npos);
  EXPECT_NE(live.out.find("# connected: serial:"), std::string::npos) << "events go to stderr";
  EXPECT_NE(live.out.find("send->receive: p50"), std::string::npos) << "statistics at the end";
}

TEST(CliListen, CommandsAndTheirExitCodes) {
  TempDir dir("listen");
  BoardProcess board("pty:" + dir / "tty", 1, 1, 30);
  const CliRun ok = run_tlvlink("listen --serial " + dir / "tty" +
                                " -c start -c 'closed 3' -c ping -c info --exit-after-replies");
  EXPECT_RUN(ok, 0);
  EXPECT_NE(ok.out.find("ack    #"), std::string::npos) << ok.out;
  EXPECT_NE(ok.out.find("pong   #"), std::string::npos) << ok.out;
  const CliRun refused =
      run_tlvlink("listen --serial " + dir / "tty" + " -c 'set bad=1' --exit-after-replies");
  EXPECT_RUN(refused, 1);
  EXPECT_NE(refused.out.find("set_config: unknown key 'bad'"), std::string::npos) << refused.out;
}

TEST(CliListen, AbsentDeviceAndBadInput) {
  const CliRun absent = run_tlvlink("listen --serial /dev/tlvlink-absent --no-reconnect");
  EXPECT_RUN(absent, 1);
  EXPECT_NE(absent.out.find("transport.unavailable"), std::string::npos) << absent.out;
  EXPECT_RUN(run_tlvlink("listen --serial /dev/x -c 'launch rockets'"), 2);
  EXPECT_RUN(run_tlvlink("listen"), 2);
  const CliRun notrec = run_tlvlink("replay /etc/hostname");
  EXPECT_RUN(notrec, 1);
  EXPECT_NE(notrec.out.find("not a tlvlink recording"), std::string::npos) << notrec.out;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Issue 31 item 3: --record refuses an existing recording without --overwrite, exit 2 (it was
// replaced silently), and a file-size limit stops the session with the path and the reason, exit 1
// (it stopped recording at 16 KB while predictions kept printing, exit 0).
TEST(CliListen, RecordKeepsAnExistingFileAndStopsOnAFailedWrite) {
  TempDir dir("listen");
  const std::string old = dir / "old.tlvrec";
  { std::ofstream(old) << "yesterday"; }
  const CliRun refused =
      run_tlvlink("listen --serial " + dir / "tty" + " --no-reconnect --record " + old);
  EXPECT_RUN(refused, 2);  // a usage error, as `tlvlink record` makes it
  EXPECT_NE(refused.out.find(old + " already exists (give --overwrite"), std::string::npos)
      << refused.out;
  EXPECT_EQ(slurp(old), "yesterday");

  BoardProcess board("pty:" + dir / "tty", 5000, 2000, 3);
  // --overwrite replaces it.
  const CliRun again = run_tlvlink(
      "listen --serial " + dir / "tty" + " --count 5 --duration 20 --overwrite --record " + old,
      Stderr::kDropped);
  EXPECT_RUN(again, 0);
  EXPECT_EQ(slurp(old).substr(0, 7), "TLVLREC");

  const std::string rec = dir / "limited.tlvrec";
  const CliRun limited =
      run_cli("timeout 30 bash",
              "-c 'ulimit -f 16; exec \"$0\" \"$@\"' " TLVLINK_CLI_BINARY " listen --serial " +
                  dir / "tty" + " --count 4000 --duration 20 --record " + rec,
              Stderr::kMerged);
  EXPECT_RUN(limited, 1);
  EXPECT_NE(limited.out.find("writing recording " + rec + ": file size limit reached"),
            std::string::npos)
      << limited.out.substr(limited.out.size() > 2000 ? limited.out.size() - 2000 : 0);
  EXPECT_LE(std::filesystem::file_size(rec), 16384u);
}

// Item 5: a FIFO as --record or as the recording to replay is refused at once (it hung, deaf to
// SIGTERM). Every run is under `timeout 30` (exit 124 = it hung).
TEST(CliListen, FifosAreRefusedWithoutHanging) {
  TempDir dir("listen");
  const std::string fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const CliRun replay = run_cli("timeout -k 5 30 " TLVLINK_CLI_BINARY, "replay " + fifo);
  EXPECT_RUN(replay, 1);
  EXPECT_NE(replay.out.find(fifo + ": not a regular file (FIFO)"), std::string::npos) << replay.out;
  const CliRun record =
      run_cli("timeout -k 5 30 " TLVLINK_CLI_BINARY,
              "listen --serial " + dir / "tty" + " --no-reconnect --record " + fifo);
  EXPECT_RUN(record, 1);
  EXPECT_NE(record.out.find(fifo + ": not a regular file (FIFO)"), std::string::npos) << record.out;
}

// Item 4: a frame whose string is not UTF-8: `replay --json` prints it (U+FFFD for the bad
// bytes) and every message after it, exit 0 (it died of an uncaught JSON exception).
TEST(CliListen, NonUtf8StringDoesNotEndTheJsonOutput) {
  TempDir dir("listen");
  ASSERT_TRUE(listen::write_non_utf8_recording(dir / "r.tlvrec").ok());
  const CliRun r = run_tlvlink("replay " + dir / "r.tlvrec" + " --json", Stderr::kDropped);
  EXPECT_RUN(r, 0);
  const auto lines = json_lines(r.out);
  ASSERT_EQ(lines.size(), 3u) << r.out;
  EXPECT_EQ(lines[1]["text"], "bad \xEF\xBF\xBD\xEF\xBF\xBD bytes");
  EXPECT_EQ(lines[2]["text"], "after");
}

}  // namespace
}  // namespace tlvlink::testing
