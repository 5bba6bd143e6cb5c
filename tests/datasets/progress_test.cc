// Progress reporter: the rate/ETA arithmetic, quiet output off a terminal or in CI, and the
// redraw rate on a terminal.

#include "tlvlink/io/progress.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <string>

namespace tlvlink::tools {
namespace {

std::string read_all(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string s;
  for (int c; (c = std::fgetc(f)) != EOF;) s.push_back(static_cast<char>(c));
  return s;
}

TEST(Progress, Figures) {
  ProgressFigures f = progress_figures(50, 200, 10.0);
  EXPECT_DOUBLE_EQ(f.fraction, 0.25);
  EXPECT_DOUBLE_EQ(f.rate_per_s, 5.0);
  EXPECT_DOUBLE_EQ(f.eta_s, 30.0);
  f = progress_figures(0, 200, 10.0);  // no rate yet: ETA unknown
  EXPECT_DOUBLE_EQ(f.rate_per_s, 0.0);
  EXPECT_LT(f.eta_s, 0.0);
  f = progress_figures(10, 200, 0.0);  // no time yet
  EXPECT_DOUBLE_EQ(f.rate_per_s, 0.0);
  EXPECT_LT(f.eta_s, 0.0);
  f = progress_figures(10, 0, 2.0);  // unknown total
  EXPECT_DOUBLE_EQ(f.fraction, 0.0);
  EXPECT_DOUBLE_EQ(f.rate_per_s, 5.0);
  EXPECT_LT(f.eta_s, 0.0);
  f = progress_figures(300, 200, 3.0);  // overshoot clamps
  EXPECT_DOUBLE_EQ(f.fraction, 1.0);
  EXPECT_DOUBLE_EQ(f.eta_s, 0.0);
}

TEST(Progress, FormatDuration) {
  EXPECT_EQ(format_duration(0.44), "0.4s");
  EXPECT_EQ(format_duration(42), "42s");
  EXPECT_EQ(format_duration(185), "3m05s");
  EXPECT_EQ(format_duration(7620), "2h07m");
  EXPECT_EQ(format_duration(-1), "--");
}

TEST(Progress, NotATerminalPrintsOnlyTheSummary) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  double now = 0;
  {
    Progress p("writing", 100, f, ProgressMode::kAuto, [&] { return now; });
    EXPECT_FALSE(p.interactive());
    for (int i = 1; i <= 100; ++i) {
      now += 0.5;
      p.set(i);
    }
    EXPECT_EQ(p.redraws(), 0);
    p.finish("12 MB");
    p.finish();  // idempotent
  }
  const std::string out = read_all(f);
  std::fclose(f);
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  EXPECT_EQ(out.find('\r'), std::string::npos);
  EXPECT_EQ(out, "writing: 100/100 in 50s (2.0/s), 12 MB\n");
}

TEST(Progress, TerminalDetectionHonoursCi) {
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0)
    GTEST_SKIP() << "no pseudo-terminal available here";
  const char* name = ptsname(master);
  ASSERT_NE(name, nullptr);
  std::FILE* tty = std::fopen(name, "w");
  ASSERT_NE(tty, nullptr);
  const char* old = std::getenv("CI");
  const std::string saved = old ? old : "";
  unsetenv("CI");
  EXPECT_TRUE(progress_is_interactive(tty));
  setenv("CI", "true", 1);
  EXPECT_FALSE(progress_is_interactive(tty));
  if (old)
    setenv("CI", saved.c_str(), 1);
  else
    unsetenv("CI");
  std::fclose(tty);
  close(master);
}

TEST(Progress, TerminalRedrawsAtMostFiveTimesASecond) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  double now = 0;
  Progress p("gen", 1000, f, ProgressMode::kInteractive, [&] { return now; });
  for (int i = 1; i <= 1000; ++i) {
    now += 0.01;  // 10 s in all
    p.set(i);
  }
  // 10 s at <= 5 Hz, plus the first draw and the final (done == total) one.
  EXPECT_LE(p.redraws(), static_cast<int64_t>(10 * kProgressRedrawHz) + 2);
  EXPECT_GE(p.redraws(), static_cast<int64_t>(10 * kProgressRedrawHz) - 2);
  p.finish();
  const std::string out = read_all(f);
  std::fclose(f);
  EXPECT_NE(out.find("\rgen 1000/1000 (100.0%)  100/s  ETA 0.0s"), std::string::npos) << out;
  EXPECT_NE(out.find("gen: 1000/1000 in 10s (100/s)\n"), std::string::npos) << out;
}

}  // namespace
}  // namespace tlvlink::tools
