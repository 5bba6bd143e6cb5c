// Recorded raw streams: what the writer stores the reader gives back byte for byte; damaged files
// are errors naming the offset or skipped-and-counted frames; replay paces, skips stale frames,
// loops and ends like a camera would.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/capture/recording.h"
#include "tlvlink/capture/replay_source.h"
#include "tlvlink/clock.h"
#include "tlvlink/crc32.h"

namespace tlvlink::capture {
namespace {

constexpr int64_t kMs = 1'000'000;
constexpr int32_t kW = 16, kH = 8;  // YUYV: 256 bytes a frame

std::string temp_path(const char* name) {
  return (std::filesystem::temp_directory_path() /
          (std::string("tlvlink_replay_") + std::to_string(::getpid()) + "_" + name))
      .string();
}

std::vector<uint8_t> frame_bytes(int k) {
  std::vector<uint8_t> b(static_cast<size_t>(kW * kH * 2));
  for (size_t i = 0; i < b.size(); ++i) b[i] = static_cast<uint8_t>(k * 7 + static_cast<int>(i));
  return b;
}

RecordingFormat yuyv_format() {
  RecordingFormat f;
  f.format = {image::PixelFormat::kYuyv, kW, kH, kW * 2};
  f.fps_numerator = 25;
  return f;
}

// Frames 0..n-1 at 40 ms; frame 3 repeats frame 1's bytes.
std::string write_recording(const char* name, int n) {
  const std::string path = temp_path(name);
  std::remove(path.c_str());
  WriterOptions o;
  o.origin_ns = 1000 * kMs;
  auto w = RecordingWriter::create(path, yuyv_format(), o);
  EXPECT_TRUE(w.ok()) << w.error().message();
  RecordedBytes one{};
  for (int k = 0; k < n; ++k) {
    const int64_t t = 1000 * kMs + k * 40 * kMs;
    if (k == 3) {
      EXPECT_TRUE(w->append_repeat(one, t, static_cast<uint32_t>(k)).ok());
      continue;
    }
    auto r = w->append(frame_bytes(k), t, static_cast<uint32_t>(k));
    EXPECT_TRUE(r.ok()) << r.error().message();
    if (k == 1) one = *r;
  }
  EXPECT_TRUE(w->close().ok());
  return path;
}

std::vector<uint8_t> expected(int k) { return frame_bytes(k == 3 ? 1 : k); }

TEST(Recording, ReaderGivesBackWhatTheWriterStored) {
  const std::string path = write_recording("roundtrip", 6);
  auto r = RecordingReader::open(path);
  ASSERT_TRUE(r.ok()) << r.error().message();
  const RecordingSummary& s = r->summary();
  EXPECT_EQ(s.frames, 6u);
  EXPECT_EQ(s.repeats, 1u);
  EXPECT_EQ(s.format.format.format, image::PixelFormat::kYuyv);
  EXPECT_EQ(s.format.format.width, kW);
  EXPECT_EQ(s.format.nominal_fps(), 25.0);
  EXPECT_EQ(s.last_offset_ns, 200 * kMs);
  EXPECT_EQ(s.truncated_records, 0u);
  std::vector<uint8_t> buf(s.max_frame_bytes);
  uint64_t at = r->first_record();
  for (int k = 0; k < 6; ++k) {
    RecordInfo info;
    auto have = r->record_at(at, info);
    ASSERT_TRUE(have.ok() && *have) << k;
    EXPECT_EQ(info.sequence, static_cast<uint32_t>(k));
    EXPECT_EQ(info.offset_ns, k * 40 * kMs);
    ASSERT_TRUE(r->read_frame(info, buf, true).ok());
    EXPECT_EQ(std::vector<uint8_t>(buf.begin(), buf.begin() + info.bytes), expected(k)) << k;
    at = info.next;
  }
  RecordInfo end;
  auto after_last = r->record_at(at, end);
  ASSERT_TRUE(after_last.ok());
  EXPECT_FALSE(*after_last);
  std::remove(path.c_str());
}

TEST(Recording, TruncatedTailIsIgnoredAndCountedCorruptionNamesTheOffset) {
  const std::string path = write_recording("damaged", 5);
  const auto size = std::filesystem::file_size(path);
  std::filesystem::resize_file(path, size - 100);  // a writer died inside the last record
  {
    auto r = RecordingReader::open(path);
    ASSERT_TRUE(r.ok()) << r.error().message();
    EXPECT_EQ(r->summary().frames, 4u);
    EXPECT_EQ(r->summary().truncated_records, 1u);
  }
  {  // a flipped byte in the second record's header
    const int fd = ::open(path.c_str(), O_RDWR);
    const uint64_t second = kRecordingHeaderBytes + kRecordHeaderBytes + kW * kH * 2;
    const uint8_t x = 0x5A;
    ASSERT_EQ(::pwrite(fd, &x, 1, static_cast<off_t>(second + 10)), 1);
    ::close(fd);
    auto r = RecordingReader::open(path);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code(), ErrorCode::kFormat);
    EXPECT_NE(std::string(r.error().message()).find("record 1 at offset " + std::to_string(second)),
              std::string::npos)
        << r.error().message();
  }
  {  // not a recording at all
    const std::string other = temp_path("not_a_recording");
    FILE* f = std::fopen(other.c_str(), "wb");
    std::fputs("just some text that is long enough to fill a sixty-four byte header, surely", f);
    std::fclose(f);
    auto r = RecordingReader::open(other);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(std::string(r.error().message()).find("not a tlvlink recording"), std::string::npos);
    std::remove(other.c_str());
  }
  std::remove(path.c_str());
}

TEST(Replay, DeliversEveryFrameThenEndsOrLoops) {
  const std::string path = write_recording("replay", 5);
  ReplayConfig c;
  c.path = path;
  c.realtime = false;
  auto src = make_replay_source(c);
  ASSERT_TRUE(src.ok());
  ASSERT_TRUE((*src)->start().ok());
  for (int k = 0; k < 5; ++k) {
    auto f = (*src)->next(100);
    ASSERT_TRUE(f.ok()) << f.error().message();
    EXPECT_EQ(f->sequence, static_cast<uint64_t>(k));
    EXPECT_EQ(std::vector<uint8_t>(f->bytes.begin(), f->bytes.end()), expected(k));
  }
  auto end = (*src)->next(100);
  ASSERT_FALSE(end.ok());
  EXPECT_EQ(end.error().code(), ErrorCode::kCaptureEndOfStream);
  EXPECT_EQ((*src)->stats().delivered, 5u);

  c.loop = true;
  auto looped = make_replay_source(c);
  ASSERT_TRUE((*looped)->start().ok());
  for (int k = 0; k < 12; ++k) {
    auto f = (*looped)->next(100);
    ASSERT_TRUE(f.ok()) << f.error().message();
    EXPECT_EQ(f->sequence, static_cast<uint64_t>(k));  // sequences continue across passes
    EXPECT_EQ(std::vector<uint8_t>(f->bytes.begin(), f->bytes.end()), expected(k % 5));
  }
  EXPECT_EQ((*looped)->stats().dropped, 0u);
  std::remove(path.c_str());
}

TEST(Replay, CorruptFrameIsCountedAndSkipped) {
  const std::string path = write_recording("corrupt_frame", 5);
  const int fd = ::open(path.c_str(), O_RDWR);
  const uint64_t third_bytes = kRecordingHeaderBytes + 3 * kRecordHeaderBytes + 2 * kW * kH * 2;
  const uint8_t x = 0xFF;
  ASSERT_EQ(::pwrite(fd, &x, 1, static_cast<off_t>(third_bytes + 5)), 1);  // frame 2's data
  ::close(fd);
  ReplayConfig c;
  c.path = path;
  c.realtime = false;
  auto src = make_replay_source(c);
  ASSERT_TRUE((*src)->start().ok());
  std::vector<uint64_t> seqs;
  for (;;) {
    auto f = (*src)->next(100);
    if (!f.ok()) break;
    seqs.push_back(f->sequence);
  }
  EXPECT_EQ(seqs, (std::vector<uint64_t>{0, 1, 3, 4}));
  EXPECT_EQ((*src)->stats().flagged_error, 1u);
  std::remove(path.c_str());
}

// Read at speed: every frame at once, none skipped, each stamped with the recorded spacing (what
// runs on frame times, the smoothing and the grasp timing, must see the camera's pace).
TEST(Replay, AtSpeedEveryFrameKeepsItsRecordedTime) {
  const std::string path = write_recording("at_speed", 10);  // 10 frames over 360 ms
  FakeClock clock;
  ReplayConfig c;
  c.path = path;
  c.realtime = false;
  auto src = make_replay_source(c);
  ASSERT_TRUE((*src)->start().ok());
  auto first = (*src)->next(1000);
  ASSERT_TRUE(first.ok());
  for (uint64_t k = 1; k < 10; ++k) {
    clock.advance_ms(3);  // a consumer far faster than the camera
    auto f = (*src)->next(1000);
    ASSERT_TRUE(f.ok()) << f.error().message();
    EXPECT_EQ(f->sequence, k);
    EXPECT_EQ(f->skipped_before, 0u);
    EXPECT_EQ(f->timestamp_ns - first->timestamp_ns, static_cast<int64_t>(k) * 40 * kMs);
  }
  EXPECT_EQ((*src)->stats().skipped_stale, 0u);
  std::remove(path.c_str());
}

TEST(Replay, RealtimeKeepsTheCamerasPaceAndSkipsStaleFrames) {
  const std::string path = write_recording("realtime", 10);  // 10 frames over 360 ms
  FakeClock clock;
  ReplayConfig c;
  c.path = path;
  auto src = make_replay_source(c);
  ASSERT_TRUE((*src)->start().ok());
  auto first = (*src)->next(1000);
  ASSERT_TRUE(first.ok());
  EXPECT_EQ(first->sequence, 0u);
  // A consumer busy for 130 ms: the frames that became due meanwhile (40, 80, 120 ms) are
  // skipped for the newest.
  clock.advance_ms(130);
  auto f = (*src)->next(1000);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->sequence, 3u);
  EXPECT_EQ(f->skipped_before, f->sequence - 1);
  EXPECT_EQ(f->timestamp_ns - first->timestamp_ns,
            static_cast<int64_t>(f->sequence) * 40 * kMs);  // the recorded spacing, exactly
  EXPECT_EQ((*src)->stats().skipped_stale, f->sequence - 1);
  EXPECT_EQ((*src)->stats().dropped, 0u) << "a stale skip counted again as a sequence gap";
  std::remove(path.c_str());
}

TEST(Replay, FramesDueBeforeTheFirstReadKeepTheRecordingsNumbers) {
  // A daemon starts its replay, then loads its model: frames that fell due meanwhile are skipped
  // as stale, and the first frame delivered keeps its recorded sequence (it was numbered 0,
  // shifting every later frame against the recording and its ground truth).
  const std::string path = write_recording("late_reader", 10);  // 10 frames, 40 ms apart
  FakeClock clock;
  ReplayConfig c;
  c.path = path;
  auto src = make_replay_source(c);
  ASSERT_TRUE((*src)->start().ok());
  clock.advance_ms(130);
  auto f = (*src)->next(1000);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->sequence, 3u);
  EXPECT_EQ(f->skipped_before, f->sequence);  // every earlier frame, counted as stale
  EXPECT_EQ((*src)->stats().skipped_stale, f->sequence);
  std::remove(path.c_str());
}

TEST(Replay, NoFrameBeforeItsTimeIsATimeout) {
  // The first frame is recorded 300 ms after the origin: asking with 1 ms to spare times out.
  const std::string path = temp_path("late_first");
  std::remove(path.c_str());
  WriterOptions o;
  o.origin_ns = 0;
  auto w = RecordingWriter::create(path, yuyv_format(), o);
  ASSERT_TRUE(w.ok());
  ASSERT_TRUE(w->append(frame_bytes(0), 300 * kMs, 0).ok());
  ASSERT_TRUE(w->close().ok());
  FakeClock clock;  // the replay's waits move it instead of taking 300 ms
  const int64_t t0 = clock.now_ns();
  ReplayConfig c;
  c.path = path;
  auto src = make_replay_source(c);
  ASSERT_TRUE((*src)->start().ok());
  auto none = (*src)->next(1);
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error().code(), ErrorCode::kCaptureTimeout);
  EXPECT_EQ((*src)->stats().timeouts, 1u);
  EXPECT_EQ(clock.now_ns() - t0, 1 * kMs) << "the timeout waited exactly its 1 ms";
  auto f = (*src)->next(2000);
  ASSERT_TRUE(f.ok()) << f.error().message();
  EXPECT_EQ(f->timestamp_ns - t0, 300 * kMs) << "delivered when it fell due";
  std::remove(path.c_str());
}

}  // namespace
}  // namespace tlvlink::capture

namespace tlvlink::capture {
namespace {

// Issue 31: a record whose length is forged (its header checksum made valid again) ends the scan
// early; the replay says so and counts the lost frame instead of ending as if the file were whole.
TEST(Replay, ForgedRecordLengthIsCountedAndNamedAtTheEnd) {
  const std::string path = write_recording("forged", 10);
  const uint64_t third = kRecordingHeaderBytes + 2 * (kRecordHeaderBytes + kW * kH * 2);
  const int fd = ::open(path.c_str(), O_RDWR);
  uint8_t h[kRecordHeaderBytes];
  ASSERT_EQ(::pread(fd, h, sizeof h, static_cast<off_t>(third)), static_cast<ssize_t>(sizeof h));
  const uint32_t forged = 1u << 20;  // within the limit, past the end of the file
  for (int i = 0; i < 4; ++i) h[20 + i] = static_cast<uint8_t>(forged >> (8 * i));
  const uint32_t crc = crc32(h, 28);
  for (int i = 0; i < 4; ++i) h[28 + i] = static_cast<uint8_t>(crc >> (8 * i));
  ASSERT_EQ(::pwrite(fd, h, sizeof h, static_cast<off_t>(third)), static_cast<ssize_t>(sizeof h));
  ::close(fd);
  ReplayConfig c;
  c.path = path;
  c.realtime = false;
  auto src = make_replay_source(c);
  ASSERT_TRUE((*src)->start().ok());
  int delivered = 0;
  Error end;
  for (;;) {
    auto f = (*src)->next(100);
    if (!f.ok()) {
      end = f.error();
      break;
    }
    ++delivered;
  }
  EXPECT_EQ(delivered, 2);
  EXPECT_EQ(end.code(), ErrorCode::kCaptureEndOfStream);
  EXPECT_NE(std::string(end.message()).find("incomplete last record ignored"), std::string::npos)
      << end.message();
  EXPECT_EQ((*src)->stats().short_frames, 1u);
  std::remove(path.c_str());
}

// Issue 31 item 8: frames due before the first read are skipped as stale even when the frame
// read next is a warm-up frame (they went uncounted); every recorded frame up to the one
// delivered is counted exactly once: stale, warm-up or delivered, never also as a gap.
TEST(Replay, EveryFrameBeforeTheFirstDeliveredIsCountedOnce) {
  const std::string path = write_recording("warmup_stale", 10);  // 10 frames, 40 ms apart
  ReplayConfig c;
  c.path = path;
  c.warmup_frames = 1;
  FakeClock clock;
  auto src = make_replay_source(c);
  ASSERT_TRUE((*src)->start().ok());
  clock.advance_ms(130);
  auto f = (*src)->next(1000);
  ASSERT_TRUE(f.ok()) << f.error().message();
  const SourceStats& st = (*src)->stats();
  EXPECT_EQ(st.warmup_discarded, 1u);
  EXPECT_EQ(st.skipped_stale + st.warmup_discarded + st.delivered, f->sequence + 1)
      << "stale " << st.skipped_stale << ", warm-up " << st.warmup_discarded << ", delivered #"
      << f->sequence;
  EXPECT_EQ(st.dropped, 0u);
  std::remove(path.c_str());
}

// Looping over a recording in which no frame is good must end, not spin inside next().
TEST(Replay, LoopWithNoGoodFrameIsAnErrorNotASpin) {
  const std::string path = write_recording("all_bad", 5);
  const int fd = ::open(path.c_str(), O_RDWR);
  uint64_t at = kRecordingHeaderBytes;
  for (int k = 0; k < 5; ++k) {
    const uint8_t x = 0xA5;
    const bool repeat = k == 3;  // repeats frame 1's bytes, already damaged
    if (!repeat) {
      ASSERT_EQ(::pwrite(fd, &x, 1, static_cast<off_t>(at + kRecordHeaderBytes + 1)), 1);
    }
    at += kRecordHeaderBytes + (repeat ? kRepeatStoredBytes : kW * kH * 2);
  }
  ::close(fd);
  ReplayConfig c;
  c.path = path;
  c.realtime = false;
  c.loop = true;
  auto src = make_replay_source(c);
  ASSERT_TRUE((*src)->start().ok());
  const auto t0 = std::chrono::steady_clock::now();
  auto f = (*src)->next(100);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1));
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.error().code(), ErrorCode::kFormat);
  EXPECT_NE(std::string(f.error().message()).find("no good frame in a whole pass"),
            std::string::npos)
      << f.error().message();
  std::remove(path.c_str());
}

TEST(Replay, AFifoIsRefusedWithoutBlocking) {
  const std::string fifo = temp_path("fifo");
  std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto r = RecordingReader::open(fifo);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(std::string(r.error().message()).find("not a regular file (FIFO)"), std::string::npos)
      << r.error().message();
  std::remove(fifo.c_str());
}

}  // namespace
}  // namespace tlvlink::capture
