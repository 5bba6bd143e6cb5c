// AtomicFile: a write that fails half-way (file-size limit, read-only directory) leaves the
// previous file byte-identical and no temporary behind.
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/temp_dir.h"
#include "tlvlink/atomic_file.h"

namespace tlvlink {
namespace {

namespace fs = std::filesystem;

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void spit(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

int temporaries_in(const std::string& dir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir))
    n += e.path().filename().string().find(".tmp-") != std::string::npos;
  return n;
}

TEST(AtomicFile, ReplacesTheFileAndKeepsItsMode) {
  testing::TempDir dir("atomic");
  const std::string path = dir / "out.bin";
  spit(path, "old");
  ASSERT_EQ(::chmod(path.c_str(), 0640), 0);
  const std::string text = "new contents";
  ASSERT_TRUE(write_file_atomic(path.c_str(), std::as_bytes(std::span(text))).ok());
  EXPECT_EQ(slurp(path), text);
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u);
  EXPECT_EQ(temporaries_in(dir.path()), 0);
}

TEST(AtomicFile, ANewFileGetsTheUmaskMode) {
  testing::TempDir dir("atomic");
  const std::string path = dir / "new.bin";
  const mode_t mask = ::umask(022);
  ::umask(mask);
  ASSERT_TRUE(write_file_atomic(path.c_str(), std::as_bytes(std::span("x", 1))).ok());
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0666u & ~mask);
}

TEST(AtomicFile, WithoutCommitTheOldFileStays) {
  testing::TempDir dir("atomic");
  const std::string path = dir / "out.bin";
  spit(path, "old");
  {
    auto f = AtomicFile::create(path.c_str());
    ASSERT_TRUE(f.ok()) << f.error().message();
    ASSERT_TRUE(f->write("partial", 7).ok());
  }  // dropped: abandoned
  EXPECT_EQ(slurp(path), "old");
  EXPECT_EQ(temporaries_in(dir.path()), 0);
}

// The file-size limit (ulimit -f) in a child: the write fails with EFBIG ("file size limit
// reached", SIGXFSZ ignored as tlvlink's main does); the parent checks the files.
TEST(AtomicFile, FileSizeLimitLeavesTheOldFileIdentical) {
  testing::TempDir dir("atomic");
  const std::string path = dir / "model.tlvm";
  const std::string old(3000, 'o');
  spit(path, old);
  int pipe_fd[2];
  ASSERT_EQ(::pipe(pipe_fd), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    const std::vector<std::byte> big(64 * 1024, std::byte{'n'});
    const Status s = write_file_atomic(path.c_str(), big);
    const std::string msg = s.ok() ? "ok" : s.error().message();
    (void)!::write(pipe_fd[1], msg.data(), msg.size());
    ::_exit(s.ok() ? 0 : 1);
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
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("file size limit reached"), std::string::npos) << msg;
  EXPECT_EQ(slurp(path), old);
  EXPECT_EQ(temporaries_in(dir.path()), 0);
}

TEST(AtomicFile, ReadOnlyDirectoryIsAnErrorNamingThePath) {
  if (::geteuid() == 0) GTEST_SKIP() << "root writes into read-only directories";
  testing::TempDir dir("atomic");
  const std::string path = dir / "out.bin";
  spit(path, "old");
  ASSERT_EQ(::chmod(dir.path().c_str(), 0500), 0);
  const std::string text = "new";
  const Status s = write_file_atomic(path.c_str(), std::as_bytes(std::span(text)));
  ::chmod(dir.path().c_str(), 0700);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(std::string(s.error().message()).find(path), std::string::npos) << s.error().message();
  EXPECT_EQ(slurp(path), "old");
}

// A real full disk: a 64 KiB tmpfs mounted over a temporary directory (needs CAP_SYS_ADMIN;
// skipped, saying so, where mounting is not allowed). The old file stays, no temporary is left.
TEST(AtomicFile, DiskFullLeavesTheOldFileIdentical) {
  testing::TempDir dir("atomic_full");
  const std::string mnt = dir / "small";
  ASSERT_EQ(::mkdir(mnt.c_str(), 0700), 0);
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=64k") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
  const std::string path = mnt + "/model.tlvm";
  const std::string old(16 * 1024, 'o');
  spit(path, old);
  const std::vector<std::byte> big(256 * 1024, std::byte{0x5a});  // more than is left
  const Status s = write_file_atomic(path.c_str(), big);
  const std::string after = slurp(path);
  const int temps = temporaries_in(mnt);
  ::umount(mnt.c_str());
  ASSERT_FALSE(s.ok());
  EXPECT_NE(std::string(s.error().message()).find("disk full"), std::string::npos)
      << s.error().message();
  EXPECT_NE(std::string(s.error().message()).find(path), std::string::npos) << s.error().message();
  EXPECT_EQ(after, old);
  EXPECT_EQ(temps, 0);
}

TEST(AtomicFile, WriteErrorTextNamesDiskFull) {
  EXPECT_STREQ(write_error_text(ENOSPC), "disk full");
  EXPECT_STREQ(write_error_text(EFBIG), "file size limit reached");
}

}  // namespace
}  // namespace tlvlink
