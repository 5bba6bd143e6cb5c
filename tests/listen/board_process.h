#pragma once
// The fake board (tlvlink_stream_check board) on a pty for the duration of a test: started with
// posix_spawn, killed by its pid at the end. The CLI tests of tests/listen and tests/foxglove
// share it; TLVLINK_STREAM_CHECK names the program.

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <string>
#include <vector>

extern char** environ;

namespace tlvlink::testing {

class BoardProcess {
 public:
  // `extra`: more board options, e.g. {"--images", "2"}.
  BoardProcess(const std::string& link, int frames, double rate, double hold_s,
               const std::vector<std::string>& extra = {}) {
    const std::string f = std::to_string(frames), r = std::to_string(rate),
                      h = std::to_string(hold_s);
    std::vector<const char*> argv = {TLVLINK_STREAM_CHECK,
                                     "board",
                                     "--link",
                                     link.c_str(),
                                     "--frames",
                                     f.c_str(),
                                     "--rate",
                                     r.c_str(),
                                     "--hold",
                                     h.c_str()};
    for (const std::string& e : extra) argv.push_back(e.c_str());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    EXPECT_EQ(
        posix_spawn(&pid_, argv[0], &actions, nullptr, const_cast<char**>(argv.data()), environ),
        0);
    posix_spawn_file_actions_destroy(&actions);
    const std::string path = link.substr(4);  // "pty:PATH"
    for (int i = 0; i < 300 && ::access(path.c_str(), F_OK) != 0; ++i) ::usleep(10'000);
  }
  ~BoardProcess() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  BoardProcess(const BoardProcess&) = delete;
  BoardProcess& operator=(const BoardProcess&) = delete;

 private:
  pid_t pid_ = -1;
};

}  // namespace tlvlink::testing
