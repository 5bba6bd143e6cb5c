// LineReader: an over-long line is cut at kMaxLineBytes + 1 bytes and skipped to its newline,
// so memory stays bounded whatever the file holds; the lines after it and the numbering are
// intact.
#include <sys/stat.h>

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "support/temp_dir.h"
#include "tlvlink/io/line_reader.h"

namespace tlvlink {
namespace {

using tools::kMaxLineBytes;
using tools::LineReader;

TEST(LineReader, OverLongLineIsCutAndSkippedToItsNewline) {
  testing::TempDir dir("lines");
  const std::string path = dir / "index.jsonl";
  {
    std::ofstream out(path, std::ios::binary);
    out << "first\n" << std::string(3 * kMaxLineBytes + 7, 'x') << "\nthird\r\nfourth";
  }
  LineReader r;
  ASSERT_TRUE(r.open(path).ok());
  std::string line;
  ASSERT_TRUE(r.next(line));
  EXPECT_EQ(line, "first");
  EXPECT_FALSE(r.too_long());
  ASSERT_TRUE(r.next(line));
  EXPECT_TRUE(r.too_long());
  EXPECT_EQ(line.size(), kMaxLineBytes + 1);
  EXPECT_EQ(r.line_number(), 2);
  ASSERT_TRUE(r.next(line));
  EXPECT_EQ(line, "third");
  EXPECT_FALSE(r.too_long());
  ASSERT_TRUE(r.next(line));
  EXPECT_EQ(line, "fourth");  // the last line needs no newline
  EXPECT_EQ(r.line_number(), 4);
  EXPECT_FALSE(r.next(line));
  EXPECT_TRUE(r.error().ok());
}

TEST(LineReader, AFifoIsNotARegularFile) {
  testing::TempDir dir("lines");
  const std::string fifo = dir / "data_list.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  LineReader r;
  const Status s = r.open(fifo);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(std::string(s.error().message()).find(fifo + ": not a regular file (FIFO)"),
            std::string::npos)
      << s.error().message();
}

}  // namespace
}  // namespace tlvlink
