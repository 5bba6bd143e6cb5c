// The MCAP writer and reader (tools/foxglove): a round trip of every record field, and every
// kind of bad input the reader must refuse with an error that names what and where.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "support/temp_dir.h"
#include "tlvlink/crc32.h"
#include "tlvlink/foxglove/mcap_reader.h"
#include "tlvlink/foxglove/mcap_writer.h"

namespace tlvlink::foxglove {
namespace {

std::vector<std::byte> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> c((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return std::vector<std::byte>(reinterpret_cast<const std::byte*>(c.data()),
                                reinterpret_cast<const std::byte*>(c.data()) + c.size());
}

std::vector<std::byte> bytes_of(const std::string& s) {
  return std::vector<std::byte>(reinterpret_cast<const std::byte*>(s.data()),
                                reinterpret_cast<const std::byte*>(s.data()) + s.size());
}

// A file with two schemas, three channels (one without schema, one with metadata) and `n`
// messages spread over chunks of at most 200 bytes of records.
std::vector<std::byte> sample_file(const std::string& path, int n) {
  McapWriterOptions o;
  o.profile = "test";
  o.chunk_bytes = 200;
  auto w = McapWriter::create(path, false, o).value();
  EXPECT_TRUE(w->add_schema({1, "a.Schema", "jsonschema", "{\"type\":\"object\"}"}).ok());
  EXPECT_TRUE(w->add_schema({7, "b.Schema", "jsonschema", "{}"}).ok());
  EXPECT_TRUE(w->add_channel({1, 1, "/a", "json", {}}).ok());
  EXPECT_TRUE(w->add_channel({2, 7, "/b", "json", {{"k", "v"}, {"x", ""}}}).ok());
  EXPECT_TRUE(w->add_channel({9, 0, "/raw", "opaque", {}}).ok());
  for (int i = 0; i < n; ++i) {
    const std::string payload = "{\"i\":" + std::to_string(i) + "}";
    const uint16_t channel = i % 3 == 0 ? 1 : i % 3 == 1 ? 2 : 9;
    EXPECT_TRUE(w->write_message(channel, 1000 + 10 * i, 2000 + i, bytes_of(payload)).ok());
  }
  EXPECT_TRUE(w->close().ok());
  return slurp(path);
}

std::string read_error(const std::vector<std::byte>& bytes) {
  Result<McapFile> r = read_mcap(bytes, "f.mcap");
  EXPECT_FALSE(r.ok());
  return r.ok() ? "" : r.error().message();
}

#define EXPECT_HAS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

TEST(Mcap, RoundTripOfEveryField) {
  testing::TempDir dir("mcap");
  const auto bytes = sample_file(dir / "f.mcap", 40);
  auto f = read_mcap(bytes, "f.mcap");
  ASSERT_TRUE(f.ok()) << f.error().message();
  EXPECT_EQ(f->profile, "test");
  EXPECT_EQ(f->library, "tlvlink");
  ASSERT_EQ(f->schemas.size(), 2u);
  EXPECT_EQ(f->schemas[1].id, 7);
  EXPECT_EQ(f->schemas[0].data, "{\"type\":\"object\"}");
  ASSERT_EQ(f->channels.size(), 3u);
  EXPECT_EQ(f->channel(2)->metadata,
            (std::vector<std::pair<std::string, std::string>>{{"k", "v"}, {"x", ""}}));
  EXPECT_EQ(f->channel(9)->schema_id, 0);
  ASSERT_EQ(f->messages.size(), 40u);
  uint32_t seq[10] = {};
  for (int i = 0; i < 40; ++i) {
    const McapMessage& m = f->messages[i];
    EXPECT_EQ(m.channel_id, i % 3 == 0 ? 1 : i % 3 == 1 ? 2 : 9);
    EXPECT_EQ(m.sequence, seq[m.channel_id]++) << "sequence counts per channel";
    EXPECT_EQ(m.log_time, 1000u + 10 * i);
    EXPECT_EQ(m.publish_time, 2000u + i);
    EXPECT_EQ(m.data, bytes_of("{\"i\":" + std::to_string(i) + "}"));
  }
  ASSERT_TRUE(f->statistics.has_value());
  EXPECT_EQ(f->statistics->message_count, 40u);
  EXPECT_GT(f->statistics->chunk_count, 3u) << "200-byte chunks: several";
  EXPECT_EQ(f->statistics->message_start_time, 1000u);
  EXPECT_EQ(f->statistics->message_end_time, 1390u);
  EXPECT_TRUE(f->data_crc_checked);
  EXPECT_TRUE(f->summary_crc_checked);
}

TEST(Mcap, AFileWithoutMessagesIsValid) {
  testing::TempDir dir("mcap");
  auto f = read_mcap(sample_file(dir / "f.mcap", 0), "f.mcap");
  ASSERT_TRUE(f.ok()) << f.error().message();
  EXPECT_EQ(f->messages.size(), 0u);
  EXPECT_EQ(f->statistics->chunk_count, 0u);
}

TEST(Mcap, ChunksCloseWhenTheirMessagesSpanTooLong) {
  testing::TempDir dir("mcap");
  McapWriterOptions o;
  o.chunk_span_ns = 100;
  auto w = McapWriter::create(dir / "f.mcap", false, o).value();
  ASSERT_TRUE(w->add_channel({1, 0, "/t", "x", {}}).ok());
  for (uint64_t t = 0; t < 1000; t += 60)
    ASSERT_TRUE(w->write_message(1, t, t, bytes_of("m")).ok());
  ASSERT_TRUE(w->close().ok());
  auto f = read_mcap_file(dir / "f.mcap");
  ASSERT_TRUE(f.ok()) << f.error().message();
  // 17 messages 60 ns apart, a chunk spans at most 100 ns: two messages a chunk.
  EXPECT_EQ(f->statistics->chunk_count, 9u);
}

TEST(McapWriter, RefusesWhatAReaderCouldNotResolve) {
  testing::TempDir dir("mcap");
  auto w = McapWriter::create(dir / "f.mcap", false).value();
  EXPECT_FALSE(w->add_schema({0, "s", "e", ""}).ok()) << "schema id 0 means no schema";
  ASSERT_TRUE(w->add_schema({1, "s", "e", ""}).ok());
  EXPECT_FALSE(w->add_schema({1, "t", "e", ""}).ok()) << "taken";
  const Status unknown_schema = w->add_channel({1, 2, "/t", "json", {}});
  ASSERT_FALSE(unknown_schema.ok());
  EXPECT_HAS(std::string(unknown_schema.error().message()), "names schema 2, which was not added");
  ASSERT_TRUE(w->add_channel({1, 1, "/t", "json", {}}).ok());
  EXPECT_FALSE(w->add_channel({1, 1, "/u", "json", {}}).ok()) << "taken";
  const Status no_channel = w->write_message(3, 0, 0, {});
  ASSERT_FALSE(no_channel.ok());
  EXPECT_HAS(std::string(no_channel.error().message()), "no channel 3");
  EXPECT_TRUE(w->close().ok());
}

TEST(McapWriter, FollowsTheRecordingFileRules) {
  testing::TempDir dir("mcap");
  const std::string path = dir / "old.mcap";
  { std::ofstream(path) << "yesterday"; }
  auto refused = McapWriter::create(path, false);
  ASSERT_FALSE(refused.ok());
  EXPECT_HAS(std::string(refused.error().message()), path + " already exists (give --overwrite");
  EXPECT_EQ(slurp(path), bytes_of("yesterday"));
  ASSERT_TRUE(McapWriter::create(path, true).ok());
  const std::string fifo = dir / "fifo.mcap";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto f = McapWriter::create(fifo, true);
  ASSERT_FALSE(f.ok());
  EXPECT_HAS(std::string(f.error().message()), "not a regular file (FIFO)");
}

// --- The reader refuses bad input, naming what and where. ---

class McapBad : public ::testing::Test {
 protected:
  void SetUp() override { good_ = sample_file(dir_ / "f.mcap", 12); }
  // Offset of the first record with this opcode (walking the top-level records).
  size_t find(uint8_t opcode) const {
    for (size_t pos = 8; pos + 9 <= good_.size();) {
      if (static_cast<uint8_t>(good_[pos]) == opcode) return pos;
      uint64_t len = 0;
      for (int i = 0; i < 8; ++i) len |= static_cast<uint64_t>(good_[pos + 1 + i]) << (8 * i);
      pos += 9 + len;
    }
    ADD_FAILURE() << "no record of opcode " << int(opcode);
    return 0;
  }
  // The file with both CRCs zeroed ("not available"): a change reaches the check it is aimed at.
  std::vector<std::byte> without_crcs() const {
    auto b = good_;
    const size_t data_end = find(0x0F), footer = good_.size() - 8 - 29;
    for (int i = 0; i < 4; ++i)
      b[data_end + 9 + i] = std::byte{0}, b[footer + 9 + 16 + i] = std::byte{0};
    return b;
  }
  testing::TempDir dir_{"mcap"};
  std::vector<std::byte> good_;
};

TEST_F(McapBad, NotMcap) {
  EXPECT_HAS(read_error(bytes_of("TLVLREC\n........")),
             "f.mcap is not an MCAP file (no MCAP magic at offset 0)");
  EXPECT_HAS(read_error({}), "not an MCAP file");
}

TEST_F(McapBad, EveryTruncationIsAnError) {
  for (size_t n = 0; n < good_.size(); ++n) {
    Result<McapFile> r = read_mcap(std::span(good_).first(n), "f.mcap");
    EXPECT_FALSE(r.ok()) << "cut to " << n << " of " << good_.size() << " bytes";
  }
  auto last = read_mcap(std::span(good_).first(good_.size() - 1), "f.mcap");
  EXPECT_HAS(std::string(last.error().message()), "not followed by the closing MCAP magic");
  auto mid = read_mcap(std::span(good_).first(find(0x0F)), "f.mcap");
  EXPECT_HAS(std::string(mid.error().message()), "no Footer record: the file ends at offset");
}

TEST_F(McapBad, ARecordLongerThanTheFile) {
  auto b = good_;
  const size_t at = find(0x03);
  b[at + 8] = std::byte{0x7F};  // length's top byte
  EXPECT_HAS(read_error(b), "Schema record at offset " + std::to_string(at) + " claims");
}

TEST_F(McapBad, AFieldLongerThanItsRecord) {
  auto b = good_;
  const size_t at = find(0x03);
  b[at + 9 + 2] = std::byte{0xFF};  // the schema name's length
  const std::string e = read_error(b);
  EXPECT_HAS(e, "Schema record, field name at offset " + std::to_string(at + 9 + 2 + 4));
  EXPECT_HAS(e, "but only");
}

TEST_F(McapBad, TheFirstRecordIsNotAHeader) {
  auto b = good_;
  b[8] = std::byte{0x0C};
  EXPECT_HAS(read_error(b),
             "the first record (offset 8) is a Metadata (opcode 0x0c), not a Header");
}

TEST_F(McapBad, SchemaIdZeroAndConflictingSchemasAndChannels) {
  auto b = good_;
  const size_t schema = find(0x03);
  b[schema + 9] = std::byte{0}, b[schema + 10] = std::byte{0};
  EXPECT_HAS(read_error(b), "schema id 0 is reserved");
  // The summary repeats schema 1 and channel 1: change the data section's copy.
  b = without_crcs();
  b[schema + 9 + 2 + 4] = std::byte{'z'};  // name "a.Schema" -> "z.Schema"
  EXPECT_HAS(read_error(b), "schema 1 defined twice with different contents");
  b = without_crcs();
  const size_t channel = find(0x04);
  b[channel + 9 + 4 + 4 + 1] = std::byte{'q'};  // topic "/a" -> "/q"
  EXPECT_HAS(read_error(b), "channel 1 defined twice with different contents");
}

TEST_F(McapBad, AChannelOnAnUnknownSchema) {
  auto b = good_;
  const size_t channel = find(0x04);
  b[channel + 9 + 2] = std::byte{5};  // schema id 1 -> 5
  EXPECT_HAS(read_error(b), "names schema 5, which no earlier Schema record defines");
}

// Chunk content: start, end, size (8 each), crc (4), compression (4 + n), records length (8),
// records.
TEST_F(McapBad, Chunks) {
  const size_t chunk = find(0x06), content = chunk + 9;
  auto b = good_;
  b[content + 24] = std::byte{0x01};  // wrong CRC
  EXPECT_HAS(read_error(b), "CRC-32 of its records is");
  b = good_;
  b[content + 16] = std::byte{0x01};  // uncompressed size
  EXPECT_HAS(read_error(b), "uncompressed_size 1 but");
  // A message on an unknown channel, a message outside the chunk's times, a Footer in a chunk:
  // CRC zeroed (not checked) so the inner records are reached.
  const size_t records = content + 8 + 8 + 8 + 4 + 4 + 8;
  auto no_crc = good_;
  for (int i = 0; i < 4; ++i) no_crc[content + 24 + i] = std::byte{0};
  b = no_crc;
  b[records + 9] = std::byte{42};
  EXPECT_HAS(read_error(b), "is on channel 42, which no earlier Channel record defines");
  b = no_crc;
  b[records + 9 + 6 + 7] = std::byte{0x10};  // log time's top byte
  EXPECT_HAS(read_error(b), "outside its chunk's");
  b = no_crc;
  b[records] = std::byte{0x02};
  EXPECT_HAS(read_error(b), "a Footer record (opcode 0x02) at offset " + std::to_string(records) +
                                " inside a chunk");
}

TEST_F(McapBad, ACompressedChunkIsNamed) {
  // A chunk whose compression is "zstd": rebuild one by hand (records empty).
  std::vector<std::byte> b(good_.begin(), good_.begin() + find(0x06));
  std::vector<std::byte> c(8 + 8 + 8 + 4, std::byte{0});
  const std::string z = "zstd";
  c.push_back(std::byte{4}), c.push_back(std::byte{0}), c.push_back(std::byte{0}),
      c.push_back(std::byte{0});
  for (char ch : z) c.push_back(std::byte(ch));
  for (int i = 0; i < 8; ++i) c.push_back(std::byte{0});
  b.push_back(std::byte{0x06});
  for (int i = 0; i < 8; ++i) b.push_back(std::byte((c.size() >> (8 * i)) & 0xFF));
  b.insert(b.end(), c.begin(), c.end());
  EXPECT_HAS(read_error(b),
             "is compressed with 'zstd'; this reader reads uncompressed chunks only");
}

TEST_F(McapBad, DataSectionAndSummaryCrcs) {
  auto b = good_;
  b[8 + 9 + 4] ^= std::byte{0x20};  // the Header's profile "test" -> "Test"
  EXPECT_HAS(read_error(b), "the data section (offsets 0..");
  b = good_;
  const size_t footer = good_.size() - 8 - 29;
  uint64_t summary = 0;
  for (int i = 0; i < 8; ++i) summary |= static_cast<uint64_t>(good_[footer + 9 + i]) << (8 * i);
  b[summary + 9 + 2 + 4] ^= std::byte{0x20};  // a letter of the summary's first Schema name
  EXPECT_HAS(read_error(b), "the summary (offsets " + std::to_string(summary));
  b = good_;
  b[footer + 9 + 7] = std::byte{0x40};  // summary_start far beyond the file
  EXPECT_HAS(read_error(b), "summary_start");
}

TEST_F(McapBad, StatisticsThatDisagreeWithTheMessages) {
  auto b = without_crcs();
  const size_t footer = good_.size() - 8 - 29;
  size_t pos = 8, stats = 0;
  while (pos < footer) {
    if (static_cast<uint8_t>(b[pos]) == 0x0B) stats = pos;
    uint64_t len = 0;
    for (int i = 0; i < 8; ++i) len |= static_cast<uint64_t>(b[pos + 1 + i]) << (8 * i);
    pos += 9 + len;
  }
  ASSERT_NE(stats, 0u);
  b[stats + 9] = std::byte{99};
  EXPECT_HAS(read_error(b), "Statistics count 99 messages");
}

TEST_F(McapBad, BytesAfterTheFooter) {
  auto b = good_;
  b.insert(b.end() - 8, std::byte{0});
  EXPECT_HAS(read_error(b), "not followed by the closing MCAP magic");
}

TEST(McapReader, FilesThatAreNotRegularAreRefused) {
  testing::TempDir dir("mcap");
  auto r = read_mcap_file(dir.path());
  ASSERT_FALSE(r.ok());
  EXPECT_HAS(std::string(r.error().message()), "not a regular file (directory)");
  auto missing = read_mcap_file(dir / "absent.mcap");
  ASSERT_FALSE(missing.ok());
  EXPECT_HAS(std::string(missing.error().message()), "absent.mcap");
}

}  // namespace
}  // namespace tlvlink::foxglove
