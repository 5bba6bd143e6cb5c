// Only regular files are read as models, images and dataset members: a FIFO, a directory or
// /dev/zero is "not a regular file" at once, never a hang or an endless read.
#include <sys/stat.h>

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "support/temp_dir.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/model_file.h"
#include "tlvlink/model.h"
#include "tlvlink/regular_file.h"

namespace tlvlink {
namespace {

void expect_not_regular(const Error& e, const std::string& path, const char* kind) {
  const std::string msg = e.message();
  EXPECT_NE(msg.find(path + ": not a regular file (" + kind + ")"), std::string::npos) << msg;
}

TEST(RegularFile, FifoDirectoryAndDeviceAreRefusedWithoutBlocking) {
  testing::TempDir dir("regular");
  const std::string fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto f = RegularFile::open(fifo.c_str());
  ASSERT_FALSE(f.ok());
  expect_not_regular(f.error(), fifo, "FIFO");
  auto d = RegularFile::open(dir.path().c_str());
  ASSERT_FALSE(d.ok());
  expect_not_regular(d.error(), dir.path(), "directory");
  auto z = RegularFile::open("/dev/zero");
  ASSERT_FALSE(z.ok());
  expect_not_regular(z.error(), "/dev/zero", "character device");
}

TEST(RegularFile, ToolReadsAndModelLoadsRefuseAFifo) {
  testing::TempDir dir("regular");
  const std::string fifo = dir / "model.tlvm";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto bytes = tools::read_file(fifo, 1 << 20);
  ASSERT_FALSE(bytes.ok());
  expect_not_regular(bytes.error(), fifo, "FIFO");
  auto model = tools::load_model(fifo);
  ASSERT_FALSE(model.ok());
  expect_not_regular(model.error(), fifo, "FIFO");
}

// The size is checked from fstat and the identifier from the first 8 bytes: a sparse file over
// kMaxModelBytes, or a large file that is not a model, costs no reading.
TEST(ModelFile, SizeAndIdentifierAreCheckedBeforeReading) {
  testing::TempDir dir("regular");
  const std::string huge = dir / "huge.tlvm";
  { std::ofstream(huge) << "x"; }
  ASSERT_EQ(::truncate(huge.c_str(), static_cast<off_t>(kMaxModelBytes) + 1), 0);
  auto m = Model::load_file(huge.c_str());
  ASSERT_FALSE(m.ok());
  EXPECT_NE(std::string(m.error().message()).find("kMaxModelBytes"), std::string::npos)
      << m.error().message();
  const std::string zeros = dir / "zeros.tlvm";
  { std::ofstream(zeros) << "12345678"; }
  ASSERT_EQ(::truncate(zeros.c_str(), static_cast<off_t>(kMaxModelBytes) - 1), 0);
  auto z = Model::load_file(zeros.c_str());
  ASSERT_FALSE(z.ok());
  EXPECT_NE(std::string(z.error().message()).find("not a tlvlink model"), std::string::npos)
      << z.error().message();
}

}  // namespace
}  // namespace tlvlink
