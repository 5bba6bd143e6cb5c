// Recordings: the fixture recording replays into exactly the messages, rejections, events and
// clock the fixture describes; a live session and the replay of its recording print identical
// JSON lines (checked in cli_listen_test); a recording cut short ends cleanly; other files are
// refused.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "fixture_recording.h"
#include "stream_fixture.h"
#include "support/temp_dir.h"
#include "tlvlink/listen/client.h"
#include "tlvlink/listen/recording.h"
#include "tlvlink/protocol/encode.h"

namespace tlvlink::listen {
namespace {

using protocol::MessageType;

std::vector<Message> replay_all(Client& c) {
  std::vector<Message> got;
  while (!c.ended()) {
    Result<std::optional<Message>> m = c.next(100);
    EXPECT_TRUE(m.ok());
    if (m.ok() && m.value()) got.push_back(std::move(*m.value()));
  }
  return got;
}

TEST(Recording, FixtureReplaysIntoWhatItDescribes) {
  testing::TempDir dir("rec");
  ASSERT_TRUE(write_fixture_recording(dir / "f.tlvrec", false).ok());
  auto c = Client::open("replay:" + dir / "f.tlvrec");
  ASSERT_TRUE(c.ok()) << c.error().message();
  const std::vector<Message> got = replay_all(*c.value());
  std::vector<MessageType> types;
  for (const Message& m : got) types.push_back(m.type());
  const std::vector<MessageType> want = {MessageType::kHello,
                                         MessageType::kFramePrediction,
                                         MessageType::kFramePrediction,
                                         MessageType::kGraspPrediction,
                                         MessageType::kGraspPrediction,
                                         MessageType::kStats,
                                         MessageType::kError,
                                         MessageType::kPong,
                                         MessageType::kNack,
                                         MessageType::kFramePrediction,
                                         MessageType::kFramePrediction,
                                         MessageType::kHello,
                                         MessageType::kFramePrediction};
  EXPECT_EQ(types, want) << "the consumed Ack (Info) and Pong (TimeSync) are not delivered";
  const LinkStats s = c.value()->stats();
  EXPECT_EQ(s.unknown_types, 1u);
  EXPECT_EQ(s.frames.version, 1u);
  EXPECT_EQ(s.frames.crc + s.frames.cobs + s.frames.truncated, 2u)
      << "garbage and the corrupted frame";
  // The corrupted frame's sequence number is missing, then 3 numbers the fixture skips.
  EXPECT_EQ(s.sequence_gaps, 2u);
  EXPECT_EQ(s.frames_missing, 4u);
  EXPECT_EQ(s.board_restarts, 1u);
  EXPECT_EQ(s.delayed, 1u);
  EXPECT_EQ(s.connects, 2u);
  EXPECT_EQ(s.disconnects, 1u);
  // The TimeSync exchange gave the board's +5 s offset exactly (symmetric 50 us legs).
  EXPECT_TRUE(got[1].clock().valid);
  EXPECT_EQ(got[1].clock().offset_ns, 5'000'000'000);
  EXPECT_FALSE(got.back().clock().valid) << "the board restarted: its clock is re-estimated";
  // The newer minor version's prediction decodes; its unknown fields are skipped.
  auto future = got[9].frame_prediction();
  ASSERT_TRUE(future.ok());
  EXPECT_EQ(future.value().frame_sequence(), 77u);
  EXPECT_TRUE(got[10].delayed());
  std::vector<LinkEvent::Kind> events;
  for (const LinkEvent& e : c.value()->take_events()) events.push_back(e.kind);
  EXPECT_EQ(events, (std::vector<LinkEvent::Kind>{
                        LinkEvent::Kind::kConnected, LinkEvent::Kind::kVersionMismatch,
                        LinkEvent::Kind::kDisconnected, LinkEvent::Kind::kConnected,
                        LinkEvent::Kind::kBoardRestarted, LinkEvent::Kind::kEndOfRecording}));
}

TEST(Recording, CutShortEndsAtTheLastWholeRecord) {
  testing::TempDir dir("rec");
  ASSERT_TRUE(write_fixture_recording(dir / "cut.tlvrec", true).ok());
  auto c = Client::open("replay:" + dir / "cut.tlvrec");
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(replay_all(*c.value()).size(), 13u);
  const auto events = c.value()->take_events();
  ASSERT_FALSE(events.empty());
  EXPECT_NE(events.back().text.find("cut short"), std::string::npos) << events.back().text;
}

TEST(Recording, WriterAndReaderRoundTrip) {
  testing::TempDir dir("rec");
  {
    auto w = RecordingWriter::create(dir / "r");
    ASSERT_TRUE(w.ok());
    const std::byte data[3] = {std::byte{1}, std::byte{0}, std::byte{2}};
    ASSERT_TRUE(w.value()->write(RecordKind::kReceived, 42, data).ok());
    ASSERT_TRUE(w.value()->write(RecordKind::kLinkDown, 43, {}).ok());
  }
  auto r = RecordingReader::open(dir / "r");
  ASSERT_TRUE(r.ok());
  EXPECT_GT(r.value()->start_wall_ns(), 1'600'000'000'000'000'000);
  Record rec;
  ASSERT_TRUE(r.value()->next(rec).value());
  EXPECT_EQ(rec.kind, RecordKind::kReceived);
  EXPECT_EQ(rec.time_ns, 42);
  EXPECT_EQ(rec.data.size(), 3u);
  ASSERT_TRUE(r.value()->next(rec).value());
  EXPECT_EQ(rec.kind, RecordKind::kLinkDown);
  EXPECT_FALSE(r.value()->next(rec).value());
  EXPECT_FALSE(r.value()->truncated());
}

TEST(Recording, OtherFilesAreRefused) {
  testing::TempDir dir("rec");
  std::FILE* f = std::fopen((dir / "not").c_str(), "wb");
  std::fputs("hello, not a recording at all, honestly", f);
  std::fclose(f);
  auto r = RecordingReader::open(dir / "not");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code(), ErrorCode::kFormat);
  EXPECT_NE(std::string(r.error().message()).find("not a tlvlink recording"), std::string::npos);
}

// Issue 31 item 3: `listen --record` refuses an existing file unless told to overwrite it (as
// `tlvlink record` does), and a FIFO or device without blocking (item 5).
TEST(Recording, AnExistingFileIsKeptUnlessOverwriteAndAFifoIsRefused) {
  testing::TempDir dir("rec");
  const std::string path = dir / "old.tlvrec";
  std::ofstream(path) << "yesterday's recording";
  auto refused = RecordingWriter::create(path);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(std::string(refused.error().message()).find(path + " already exists (give --overwrite"),
            std::string::npos)
      << refused.error().message();
  std::ifstream in(path);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "yesterday's recording");
  auto replaced = RecordingWriter::create(path, true);
  ASSERT_TRUE(replaced.ok()) << replaced.error().message();
  replaced.value().reset();
  EXPECT_TRUE(RecordingReader::open(path).ok());

  const std::string fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (bool overwrite : {false, true}) {
    auto w = RecordingWriter::create(fifo, overwrite);
    ASSERT_FALSE(w.ok());
    EXPECT_NE(std::string(w.error().message()).find("not a regular file (FIFO)"), std::string::npos)
        << w.error().message();
  }
  auto r = RecordingReader::open(fifo);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(std::string(r.error().message()).find(fifo + ": not a regular file (FIFO)"),
            std::string::npos)
      << r.error().message();
}

// A full disk or a file-size limit: the write fails with the path and the reason (it stopped at
// 16 KB silently). In a child with RLIMIT_FSIZE, SIGXFSZ ignored as tlvlink's main does.
TEST(Recording, AFailedWriteNamesThePathAndTheReason) {
  testing::TempDir dir("rec");
  const std::string path = dir / "limited.tlvrec";
  int pipe_fd[2];
  ASSERT_EQ(::pipe(pipe_fd), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{16384, 16384};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    auto w = RecordingWriter::create(path);
    std::string msg = w.ok() ? "" : w.error().message();
    const std::vector<std::byte> chunk(1000, std::byte{7});
    for (int i = 0; i < 100 && msg.empty(); ++i) {
      Status st = w.value()->write(RecordKind::kReceived, i, chunk);
      if (st.ok()) st = w.value()->flush();
      if (!st.ok()) msg = st.error().message();
    }
    (void)!::write(pipe_fd[1], msg.data(), msg.size());
    ::_exit(msg.empty() ? 0 : 1);
  }
  ::close(pipe_fd[1]);
  char buf[512] = {};
  const ssize_t n = ::read(pipe_fd[0], buf, sizeof(buf) - 1);
  ::close(pipe_fd[0]);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const std::string msg(buf, n > 0 ? static_cast<size_t>(n) : 0);
  EXPECT_NE(msg.find("writing recording " + path + ": file size limit reached"), std::string::npos)
      << msg;
}

// Issue 31 item 11: on a link shared with another host, a Pong answering that host's ping
// carries its clock's t1; the client must not take it for an exchange of its own (it estimated
// -113 s +- 113 s). Only a Pong echoing a command this client sent (sequence and send time)
// counts; the foreign one is still delivered.
TEST(Recording, APongToAnotherHostsPingDoesNotSetTheClock) {
  testing::TempDir dir("rec");
  alignas(8) static std::byte scratch[protocol::kEncodeBufferSize];
  static std::byte wire[protocol::kMaxWireFrameSize];
  constexpr int64_t kT = 1'000'000'000, kOffset = 5'000'000'000;
  {
    auto w = RecordingWriter::create(dir / "r");
    ASSERT_TRUE(w.ok());
    const auto put = [&](RecordKind kind, int64_t t, const auto& m, uint32_t seq, int64_t send_ns) {
      protocol::FrameHeader h;
      h.sequence = seq;
      h.send_ns = send_ns;
      const size_t n = protocol::encode_message(m, h, scratch, wire).value();
      ASSERT_TRUE(w.value()->write(kind, t, std::span(wire, n)).ok());
    };
    const std::string up = "serial:/dev/ttyACM0 (test)";
    ASSERT_TRUE(w.value()
                    ->write(RecordKind::kLinkUp, kT, std::as_bytes(std::span(up.data(), up.size())))
                    .ok());
    put(RecordKind::kReceived, kT + 1000, testing::fixture_hello(), 0, kT + kOffset);
    // Another host's ping #1, sent at its t1 = 7 s: its Pong reaches us too.
    put(RecordKind::kReceived, kT + 200'000,
        protocol::Pong{1, 7'000'000'000, kT + kOffset + 100'000}, 1, kT + kOffset + 110'000);
  }
  auto c = Client::open("replay:" + dir / "r");
  ASSERT_TRUE(c.ok());
  const std::vector<Message> got = replay_all(*c.value());
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[1].type(), MessageType::kPong) << "not ours: delivered, not consumed";
  EXPECT_FALSE(c.value()->clock().valid) << "offset " << c.value()->clock().offset_ns;
  EXPECT_EQ(c.value()->stats().round_trip.count(), 0u);
}

}  // namespace
}  // namespace tlvlink::listen
